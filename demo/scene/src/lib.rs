//! The built-in demo scene of the raymip bare-metal demos: a small tile
//! rendered entirely through the firmware path (fixed-point ray generation and
//! intersection, the ray stack for mirror bounces, the Pb table and table
//! LOD, texture shading), in integer arithmetic only.
//!
//! The same code runs on the host (x86-64), on Cortex-M4 and on RV32IMAC
//! under QEMU; the pixel checksum and every counter must be bit-identical on
//! all three (checked by `scripts/test-all`).
//!
//! # Scene
//!
//! A corridor seen by a pinhole camera at `(0, 0.5, 0)` looking down `−z`
//! (60° vertical field of view, [`WIDTH`] × [`HEIGHT`] pixels): a textured,
//! slightly reflective floor (`y = −1`), a textured back wall (`z = −14`), a
//! textured panel (`z = −6`) and two facing mirrors (`x = ±3`), so rays
//! bounce up to [`MAX_DEPTH`] times. Every quad is two triangles, each with
//! its own Pb table entry; mirrors are untextured (table marker, no LOD work).
//!
//! # Number formats
//!
//! Positions and hit distances: Q16.16 in `i32`/`i64` (the scene spans
//! ±16 units); unit directions: Q2.30 (`i32`); colour weights: Q0.8.
//! Divisions are checked (a zero divisor is a miss), so nothing panics.
//!
//! # Generated data
//!
//! `data.rs` is written by `cargo run -p raymip-host --bin raymip-demo --
//! gen-data` (host, with floats: the camera's pixel spread, the Pb table
//! and the textures) and checked in; a host test fails when it is stale.
//! The two texture pyramids are binary assets beside it (`tex0.bin`,
//! `tex1.bin`: RGBA8888 texels as little-endian words), embedded with
//! `include_bytes!` and turned into `[u32; N]` statics at compile time
//! ([`le_words`]), so flash holds the same words as a literal table would.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

use core::fmt;

pub mod parity;
pub mod pow2_check;

use raymip::lod::{clamp_lod, table_lod};
use raymip::path::raystack::{PathState, RayStack};
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::{PbTable, TexTriangle};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel, generate};
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Coord, Lod, Log2Pb, PathLength, Spread, TexCoord};

mod data;
pub use data::{PB_TABLE, PIXEL_SIZE_Q16, PIXEL_SPREAD_BITS, TEX0, TEX1};

/// The little-endian `u32` words of `bytes` (a generated binary asset),
/// evaluated at compile time for the texture statics of `data.rs`; a length
/// other than `4·N` bytes fails the build.
const fn le_words<const N: usize>(bytes: &[u8]) -> [u32; N] {
    assert!(bytes.len() == 4 * N, "asset length is not 4·N bytes");
    let mut words = [0u32; N];
    let mut i = 0;
    while i < N {
        let b = 4 * i;
        words[i] = u32::from_le_bytes([bytes[b], bytes[b + 1], bytes[b + 2], bytes[b + 3]]);
        i += 1;
    }
    words
}

/// Tile width in pixels.
pub const WIDTH: u32 = 64;
/// Tile height in pixels.
pub const HEIGHT: u32 = 48;
/// Vertical field of view of the camera, degrees (used by the host generator).
pub const FOV_Y_DEGREES: f64 = 60.0;
/// Longest path: primary ray plus this many bounces.
pub const MAX_DEPTH: u8 = 8;
/// Ray stack capacity of the demo (the paper's 10 entries). Each hit
/// pushes at most one continuation (the mirror term) and the tracer pops it
/// at once, so a path needs `stack_bound(MAX_DEPTH, 1) = 1` entry (derivation
/// in `raymip::path::raystack`): the stack never fills and `stack_full` stays 0.
pub const STACK: usize = 10;
const _: () = assert!(STACK >= raymip::path::raystack::stack_bound(MAX_DEPTH, 1));
/// Texture size (level 0) of both demo textures, texels per side.
pub const TEX_SIZE: u32 = 32;
/// Number of MIP levels of the demo textures (32 → 1).
pub const TEX_LEVELS: u8 = 6;
/// Texels of one demo pyramid (32² + 16² + … + 1).
pub const TEX_LEN: usize =
    raymip::texture::storage::mip::pyramid_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS);
/// Cache of texture 0 (sets × ways of 4×4-texel blocks).
pub type Tex0Cache = TexelCache<Pyramid<'static>, 8, 2>;

/// One in Q16.16.
const ONE: i32 = 1 << 16;
/// Camera height (Q16.16).
const CAM_Y: i32 = ONE / 2;
/// Smallest accepted hit distance (Q16.16): avoids re-hitting the surface a
/// ray leaves.
const T_MIN: i64 = 1 << 8;
/// Largest accepted hit distance (Q16.16): 1024 units.
const T_MAX: i64 = 1 << 26;
/// Contributions below this weight (Q0.8) are dropped.
const MIN_WEIGHT: u32 = 4;

/// What a surface does with a ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Material {
    /// Textured with demo texture `tex`; `u = a·scale`, `v = b·scale`
    /// (Q16.16 scale, a and b the in-plane coordinates), and reflecting
    /// `reflect/256` of the light (the rest is texture).
    Textured {
        /// Texture index (0 or 1).
        tex: u8,
        /// UV repeats per scene unit (Q16.16).
        scale: i32,
        /// Reflectance, Q0.8.
        reflect: u32,
    },
    /// A mirror reflecting `reflect/256`, the rest in `tint` (untextured).
    Mirror {
        /// Reflectance, Q0.8.
        reflect: u32,
        /// Own colour (RGB).
        tint: [u8; 3],
    },
}

/// An axis-aligned rectangle `x_axis = c`, `a ∈ [a0, a1]`, `b ∈ [b0, b1]`
/// where `(a, b)` are the other two axes in increasing order. Split into
/// two triangles along the diagonal `(a0, b0)–(a1, b1)`: triangle `tri`
/// below it, `tri + 1` above.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Quad {
    /// The axis the rectangle is perpendicular to (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// Plane coordinate (Q16.16).
    pub c: i32,
    /// Range of the first in-plane axis (Q16.16).
    pub a: [i32; 2],
    /// Range of the second in-plane axis (Q16.16).
    pub b: [i32; 2],
    /// Material.
    pub material: Material,
    /// Index of the first of its two triangles in the Pb table.
    pub tri: usize,
}

impl Quad {
    /// The rectangle `axis = c`, `a × b`, of `material`, first triangle
    /// `tri` (a row of [`QUADS`]).
    const fn new(
        axis: usize,
        c: i32,
        a: [i32; 2],
        b: [i32; 2],
        material: Material,
        tri: usize,
    ) -> Self {
        Self {
            axis,
            c,
            a,
            b,
            material,
            tri,
        }
    }
}

const fn q(units: i32) -> i32 {
    units * ONE
}

const fn textured(tex: u8, scale: i32, reflect: u32) -> Material {
    Material::Textured {
        tex,
        scale,
        reflect,
    }
}

const fn mirror(reflect: u32, tint: [u8; 3]) -> Material {
    Material::Mirror { reflect, tint }
}

/// The scene: floor y = −1 (texture 0, two repeats per unit, 1/4
/// reflective), back wall z = −14 (texture 1, one repeat per 4 units),
/// panel z = −6 (texture 1, one repeat per unit), right mirror x = 3, left
/// mirror x = −3.
#[rustfmt::skip]
pub const QUADS: [Quad; 5] = [
    Quad::new(1, q(-1),  [q(-3), q(3)],               [q(-14), q(-1)],      textured(0, ONE / 2, 64),  0),
    Quad::new(2, q(-14), [q(-3), q(3)],               [q(-1), q(3)],        textured(1, ONE / 4, 0),   2),
    Quad::new(2, q(-6),  [-ONE * 4 / 5, ONE * 4 / 5], [q(-1), ONE * 3 / 5], textured(1, ONE, 0),       4),
    Quad::new(0, q(3),   [q(-1), q(3)],               [q(-14), q(-1)],      mirror(224, [40, 60, 90]), 6),
    Quad::new(0, q(-3),  [q(-1), q(3)],               [q(-14), q(-1)],      mirror(208, [90, 50, 40]), 8),
];

/// Number of triangles (Pb table entries).
pub const TRIANGLES: usize = 10;

/// The in-plane axes of a quad perpendicular to `axis`.
const fn plane_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The scene's triangles as the Pb table needs them (`None` = untextured),
/// in table order. Float-free (fixed-point set-up).
#[must_use]
pub fn triangles() -> [Option<TexTriangle>; TRIANGLES] {
    let mut out = [None; TRIANGLES];
    for quad in &QUADS {
        let Material::Textured { scale, .. } = quad.material else {
            continue;
        };
        let (ia, ib) = plane_axes(quad.axis);
        let corner = |a: i32, b: i32| {
            let mut p = [Coord::ZERO; 3];
            p[quad.axis] = Coord::from_bits(i64::from(quad.c) << 16);
            p[ia] = Coord::from_bits(i64::from(a) << 16);
            p[ib] = Coord::from_bits(i64::from(b) << 16);
            let uv = [
                // Q16.16 · Q16.16 = Q32.32 = the I32F32 bits.
                TexCoord::from_bits(i64::from(a) * i64::from(scale)),
                TexCoord::from_bits(i64::from(b) * i64::from(scale)),
            ];
            (p, uv)
        };
        let [a0, a1] = quad.a;
        let [b0, b1] = quad.b;
        let (p00, t00) = corner(a0, b0);
        let (p10, t10) = corner(a1, b0);
        let (p11, t11) = corner(a1, b1);
        let (p01, t01) = corner(a0, b1);
        let lower = TexTriangle::new([p00, p10, p11], [t00, t10, t11], TEX_SIZE, TEX_SIZE).ok();
        let upper = TexTriangle::new([p00, p11, p01], [t00, t11, t01], TEX_SIZE, TEX_SIZE).ok();
        if let Some(slot) = out.get_mut(quad.tri) {
            *slot = lower;
        }
        if let Some(slot) = out.get_mut(quad.tri + 1) {
            *slot = upper;
        }
    }
    out
}

/// The camera's pixel spread angle from the generated data.
#[must_use]
pub fn pixel_spread() -> Option<PixelSpread> {
    PixelSpread::from_angle(Spread::from_bits(PIXEL_SPREAD_BITS)).ok()
}

/// The generated Pb table (static data).
#[must_use]
pub fn static_table() -> [Log2Pb; TRIANGLES] {
    PB_TABLE.map(Log2Pb::from_bits)
}

/// Per-stage counters of one render (all must match across targets).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Pixels shaded.
    pub pixels: u32,
    /// Ray segments traced (primary + secondary).
    pub segments: u32,
    /// Segments that hit a surface.
    pub hits: u32,
    /// Segments that left the scene.
    pub misses: u32,
    /// Hits on textured triangles (one table LOD each).
    pub lod_evals: u32,
    /// Hits on untextured triangles (table marker, no LOD work).
    pub untextured: u32,
    /// Sum of the clamped LODs of all textured hits (I8F8 raw units).
    pub lod_sum: u64,
    /// Texture samples taken (trilinear).
    pub samples: u32,
    /// Texels read by the samplers.
    pub texels_fetched: u64,
    /// Texel reads skipped (second level with blend weight 0).
    pub texels_skipped: u64,
    /// Block-cache hits of texture 0 (4×4-texel blocks).
    pub cache_hits: u64,
    /// Block-cache misses of texture 0.
    pub cache_misses: u64,
    /// Ray stack pushes (reflection continuations).
    pub pushes: u32,
    /// Ray stack pops.
    pub pops: u32,
    /// Pushes refused by a full stack.
    pub stack_full: u32,
    /// Continuations dropped at [`MAX_DEPTH`] or below the weight threshold.
    pub cutoffs: u32,
    /// Deepest path (bounces).
    pub max_depth: u8,
    /// Pb table entries rebuilt at start-up that differ from the static table.
    pub table_mismatches: u32,
    /// Pyramid texels regenerated at start-up that differ from the static pyramids.
    pub pyramid_mismatches: u32,
}

impl fmt::Display for Counters {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "pixels={} segments={} hits={} misses={} lod_evals={} untextured={} lod_sum={} \
             samples={} texels_fetched={} texels_skipped={} cache_hits={} cache_misses={} \
             pushes={} pops={} stack_full={} cutoffs={} max_depth={} table_mismatches={} \
             pyramid_mismatches={}",
            self.pixels,
            self.segments,
            self.hits,
            self.misses,
            self.lod_evals,
            self.untextured,
            self.lod_sum,
            self.samples,
            self.texels_fetched,
            self.texels_skipped,
            self.cache_hits,
            self.cache_misses,
            self.pushes,
            self.pops,
            self.stack_full,
            self.cutoffs,
            self.max_depth,
            self.table_mismatches,
            self.pyramid_mismatches
        )
    }
}

/// The ray geometry that travels beside a [`PathState`] on the stack.
#[derive(Clone, Copy, Debug, Default)]
struct Ray {
    /// Origin (Q16.16).
    o: [i32; 3],
    /// Unit direction (Q2.30).
    d: [i32; 3],
    /// Weight of this path's contribution (Q0.8, 256 = 1).
    w: u32,
}

/// A hit: distance (Q16.16), quad index, in-plane coordinates (Q16.16).
#[derive(Clone, Copy, Debug)]
struct Hit {
    t: i64,
    quad: usize,
    a: i32,
    b: i32,
}

fn intersect(ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (k, quad) in QUADS.iter().enumerate() {
        let ax = quad.axis;
        let (ia, ib) = plane_axes(ax);
        let (Some(&o), Some(&d)) = (ray.o.get(ax), ray.d.get(ax)) else {
            continue;
        };
        if d == 0 {
            continue;
        }
        let num = (i64::from(quad.c) - i64::from(o)) << 30;
        let Some(t) = num.checked_div(i64::from(d)) else {
            continue;
        };
        if !(T_MIN..T_MAX).contains(&t) || best.is_some_and(|h| h.t <= t) {
            continue;
        }
        let at = |i: usize| -> i32 {
            let o = ray.o.get(i).copied().unwrap_or(0);
            let d = ray.d.get(i).copied().unwrap_or(0);
            // |d·t| < 2^30 · 2^26: no overflow; result within ±2^27.
            o.saturating_add(((i64::from(d) * t) >> 30) as i32)
        };
        let (a, b) = (at(ia), at(ib));
        if a < quad.a[0] || a > quad.a[1] || b < quad.b[0] || b > quad.b[1] {
            continue;
        }
        best = Some(Hit { t, quad: k, a, b });
    }
    best
}

/// Which of the quad's two triangles `(a, b)` lies in.
fn triangle_of(quad: &Quad, a: i32, b: i32) -> usize {
    let da = i64::from(a) - i64::from(quad.a[0]);
    let db = i64::from(b) - i64::from(quad.b[0]);
    let wa = i64::from(quad.a[1]) - i64::from(quad.a[0]);
    let wb = i64::from(quad.b[1]) - i64::from(quad.b[0]);
    // Above the diagonal (a0,b0)–(a1,b1) when db·wa > da·wb.
    quad.tri + usize::from(db * wa > da * wb)
}

/// Primary ray direction of pixel `(px, py)` (unit, Q2.30).
fn primary_dir(px: u32, py: u32) -> [i32; 3] {
    let s = i64::from(PIXEL_SIZE_Q16);
    // Pixel centre offsets from the image centre, in half pixels.
    let hx = 2 * i64::from(px) + 1 - i64::from(WIDTH);
    let hy = i64::from(HEIGHT) - 2 * i64::from(py) - 1;
    let x = hx * s / 2; // Q16.16
    let y = hy * s / 2;
    let z = -i64::from(ONE);
    let len2 = (x * x + y * y + z * z) as u64; // Q32.32, < 2^40
    let len = len2.isqrt() as i64; // Q16.16, ≥ 1.0
    let n = |c: i64| (c << 30).checked_div(len).unwrap_or(0) as i32;
    [n(x), n(y), n(z)]
}

/// The level-0 texels of demo texture `tex` (0 or 1) as the host
/// generator draws them: RGBA8888, `TEX_SIZE`² texels, row-major. Texture 0
/// is a tile floor (4×4-texel cells in two tones with dark grout lines),
/// texture 1 a brick wall (8×4-texel bricks, offset every other row).
#[must_use]
pub fn texture_level0(tex: u8, x: u32, y: u32) -> Texel {
    let rgb: [u8; 3] = if tex == 0 {
        if x.is_multiple_of(4) || y.is_multiple_of(4) {
            [40, 36, 30]
        } else if ((x / 4) ^ (y / 4)) & 1 == 0 {
            [230, 200, 150]
        } else {
            [150, 90, 60]
        }
    } else {
        let row = y / 4;
        let shift = if row.is_multiple_of(2) { 0 } else { 4 };
        let bx = (x + shift) / 8;
        if y % 4 == 3 || (x + shift) % 8 == 7 {
            [200, 200, 190]
        } else {
            let k = (bx * 7 + row * 3) % 5;
            [150 + 15 * k as u8, 60 + 8 * k as u8, 40]
        }
    };
    u32::from_le_bytes([rgb[0], rgb[1], rgb[2], 255])
}

/// Geometry of both demo pyramids.
#[must_use]
pub fn tex_geometry() -> Option<Geometry> {
    Geometry::new(TEX_SIZE, TEX_SIZE, TEX_LEVELS).ok()
}

/// The first demo texture ([`TEX0`]) as a power-of-two pyramid (direct
/// level views), with its geometry: the texture the budget and cycle
/// binaries sample.
#[must_use]
pub fn tex0_pow2() -> Option<(Geometry, Pow2Pyramid<'static>)> {
    let g = tex_geometry()?;
    Some((g, Pow2Pyramid::new(Pyramid::new(g, &TEX0).ok()?).ok()?))
}

/// Pyramid texels that differ between `stored` and a pyramid regenerated
/// from its level 0 with [`raymip::texture::storage::mip::generate`] (run at start-up on
/// each target: MIP generation must be bit-identical too).
#[must_use]
pub fn regenerate_mismatches(stored: &[Texel; TEX_LEN]) -> u32 {
    let Some(g) = tex_geometry() else {
        return u32::MAX;
    };
    let mut buf = [0; TEX_LEN];
    let n0 = (TEX_SIZE * TEX_SIZE) as usize;
    if let (Some(dst), Some(src)) = (buf.get_mut(..n0), stored.get(..n0)) {
        dst.copy_from_slice(src);
    }
    if generate(&g, &mut buf).is_err() {
        return u32::MAX;
    }
    buf.iter()
        .zip(stored.iter())
        .filter(|(a, b)| a != b)
        .count() as u32
}

/// Sky colour (rays that leave the scene).
const SKY: [u32; 3] = [30, 30, 60];

/// One trilinear sample of texture `tex` (0: `tex0` through its block
/// cache, else `tex1` from memory). Out of line on purpose: inlined into
/// [`Renderer::pixel`], the two samplers' code made the optimiser keep the
/// ray stack in memory instead of registers (the pixel's frame grew from
/// 256 to 1016 bytes on the Cortex-M4).
#[inline(never)]
fn sample_tex(
    tex0: &mut Sampler<Tex0Cache>,
    tex1: &mut Sampler<Pow2Pyramid<'static>>,
    tex: u8,
    u: TexCoord,
    v: TexCoord,
    lod: Lod,
) -> Texel {
    if tex == 0 {
        tex0.sample(u, v, lod, Mode::Trilinear)
    } else {
        tex1.sample(u, v, lod, Mode::Trilinear)
    }
}

/// A renderer with its rebuilt Pb table and counters.
#[derive(Debug)]
pub struct Renderer {
    table: [Log2Pb; TRIANGLES],
    spread: PixelSpread,
    tex0: Sampler<Tex0Cache>,
    tex1: Sampler<Pow2Pyramid<'static>>,
    /// Counters so far.
    pub counters: Counters,
}

impl Renderer {
    /// Rebuilds the Pb table at start-up (fixed point, float-free) and
    /// compares it with the static one ([`Counters::table_mismatches`]).
    /// `None` if the generated pixel spread is invalid.
    #[must_use]
    pub fn new() -> Option<Self> {
        let spread = pixel_spread()?;
        let mut table = [Log2Pb::UNTEXTURED; TRIANGLES];
        PbTable::new(&mut table).build(triangles(), &spread).ok()?;
        let counters = Counters {
            table_mismatches: table
                .iter()
                .zip(static_table().iter())
                .filter(|(a, b)| a != b)
                .count() as u32,
            pyramid_mismatches: regenerate_mismatches(&TEX0)
                .saturating_add(regenerate_mismatches(&TEX1)),
            ..Counters::default()
        };
        let g = tex_geometry()?;
        let p0 = Pyramid::new(g, &TEX0).ok()?;
        let p1 = Pow2Pyramid::new(Pyramid::new(g, &TEX1).ok()?).ok()?;
        Some(Self {
            // The static table is what the firmware uses (flash data).
            table: static_table(),
            spread,
            tex0: Sampler::wrap(TexelCache::new(p0)),
            tex1: Sampler::wrap(p1),
            counters,
        })
    }

    /// Renders pixel `(px, py)` (RGB).
    pub fn pixel(&mut self, px: u32, py: u32) -> [u8; 3] {
        let c = &mut self.counters;
        c.pixels += 1;
        let mut stack: RayStack<Ray, STACK> = RayStack::new();
        let mut acc = [0u32; 3];
        let mut cur_state = PathState::primary(&self.spread, 0xFF);
        let mut cur = Ray {
            o: [0, CAM_Y, 0],
            d: primary_dir(px, py),
            w: 256,
        };
        loop {
            c.segments += 1;
            c.max_depth = c.max_depth.max(cur_state.depth);
            let mut next: Option<(PathState, Ray)> = None;
            match intersect(&cur) {
                None => {
                    c.misses += 1;
                    for (a, s) in acc.iter_mut().zip(SKY) {
                        *a += cur.w * s;
                    }
                }
                Some(hit) => {
                    c.hits += 1;
                    let quad = QUADS.get(hit.quad).copied().unwrap_or(QUADS[0]);
                    let tri = triangle_of(&quad, hit.a, hit.b);
                    // Q16.16 distance → U32F32 path length.
                    let st = cur_state.advance(PathLength::from_bits((hit.t as u64) << 16));
                    let pb = self.table.get(tri).copied().unwrap_or(Log2Pb::UNTEXTURED);
                    let (own, reflect) = match quad.material {
                        Material::Textured {
                            tex,
                            scale,
                            reflect,
                        } => match table_lod::<Accurate>(st.pl, pb) {
                            Some(lod) => {
                                c.lod_evals += 1;
                                let lod = clamp_lod(lod, TEX_LEVELS);
                                c.lod_sum += lod.to_bits() as u64;
                                // Q16.16 · Q16.16 = Q32.32: the TexCoord bits.
                                let u = TexCoord::from_bits(i64::from(hit.a) * i64::from(scale));
                                let v = TexCoord::from_bits(i64::from(hit.b) * i64::from(scale));
                                c.samples += 1;
                                let t = sample_tex(&mut self.tex0, &mut self.tex1, tex, u, v, lod);
                                let [r, g, b, _] = t.to_le_bytes();
                                ([r, g, b].map(u32::from), reflect)
                            }
                            None => {
                                c.untextured += 1;
                                ([255, 0, 255], reflect)
                            }
                        },
                        Material::Mirror { reflect, tint } => {
                            if pb.is_untextured() {
                                c.untextured += 1;
                            }
                            (tint.map(u32::from), reflect)
                        }
                    };
                    let w_own = (cur.w * (256 - reflect)) >> 8;
                    for (a, s) in acc.iter_mut().zip(own) {
                        *a += w_own * s;
                    }
                    let w_ref = (cur.w * reflect) >> 8;
                    if reflect > 0 {
                        if st.depth >= MAX_DEPTH || w_ref < MIN_WEIGHT {
                            c.cutoffs += 1;
                        } else {
                            let mut o = cur.o;
                            let (ia, ib) = plane_axes(quad.axis);
                            if let Some(v) = o.get_mut(quad.axis) {
                                *v = quad.c;
                            }
                            if let Some(v) = o.get_mut(ia) {
                                *v = hit.a;
                            }
                            if let Some(v) = o.get_mut(ib) {
                                *v = hit.b;
                            }
                            let mut d = cur.d;
                            if let Some(v) = d.get_mut(quad.axis) {
                                *v = v.saturating_neg();
                            }
                            next = Some((st.bounce(Spread::ZERO), Ray { o, d, w: w_ref }));
                        }
                    }
                }
            }
            if let Some((state, ray)) = next {
                match stack.push_with(state, ray) {
                    Ok(()) => c.pushes += 1,
                    Err(_) => c.stack_full += 1,
                }
            }
            match stack.pop_with() {
                Some((state, ray)) => {
                    c.pops += 1;
                    cur_state = state;
                    cur = ray;
                }
                None => break,
            }
        }
        acc.map(|v| (v >> 8).min(255) as u8)
    }

    /// Renders the whole tile row by row, handing each pixel to `sink`.
    pub fn render(&mut self, mut sink: impl FnMut(u32, u32, [u8; 3])) {
        for py in 0..HEIGHT {
            for px in 0..WIDTH {
                let rgb = self.pixel(px, py);
                sink(px, py, rgb);
            }
        }
        let (a, b) = (self.tex0.stats(), self.tex1.stats());
        self.counters.texels_fetched = a.fetched + b.fetched;
        self.counters.texels_skipped = a.skipped + b.skipped;
        let cache = self.tex0.source().stats();
        self.counters.cache_hits = cache.hits;
        self.counters.cache_misses = cache.misses;
    }
}

/// 32-bit FNV-1a, the demo's pixel checksum.
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(u32);

impl Default for Fnv1a {
    fn default() -> Self {
        Self(0x811C_9DC5)
    }
}

impl Fnv1a {
    /// Adds bytes.
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u32::from(b)).wrapping_mul(0x0100_0193);
        }
    }

    /// The hash so far.
    #[must_use]
    pub fn finish(&self) -> u32 {
        self.0
    }
}

/// Renders the tile and returns the checksum of its RGB bytes (row-major)
/// and the counters. `None` if the generated data is invalid.
#[must_use]
pub fn render_checksum() -> Option<(u32, Counters)> {
    let mut r = Renderer::new()?;
    let mut h = Fnv1a::default();
    r.render(|_, _, rgb| h.write(&rgb));
    Some((h.finish(), r.counters))
}
