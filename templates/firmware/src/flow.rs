// The per-hit flow of a texture-unit firmware with raymip's features
// `trilinear` (table lod, trilinear filter): set-up once, then per hit
// path state -> lod -> sample, with the continuations of every hit on a
// ray stack. Integer arithmetic only: no float, no allocator, no panic.
use raymip::lod::table_lod;
use raymip::path::raystack::stack_bound;
use raymip::texture::storage::mip::pyramid_len;
use raymip::units::{Accurate, Coord};
use raymip::{Geometry, Log2Pb, Mode, PathLength, PathState, PbTable, PixelSpread};
use raymip::{Pyramid, RayStack, Sampler, Spread, TexCoord, TexTriangle, Texel};

/// Bounces per path; every hit continues with two rays (reflection and refraction).
pub const BOUNCES: u8 = 10;
/// Ray-stack entries such paths need: `stack_bound(10, 2)` = 11.
pub const STACK: usize = stack_bound(BOUNCES, 2);
/// Pixel spread `γ = atan(2·tan(fov/2)/rows)` in radians: 60° over
/// 480 rows, worked out once on the host (`PixelSpread::from_fov_y` would
/// bring double-precision soft float and libm into the image).
pub const SPREAD: Spread = Spread::lit("0.0024056");
/// Hit distances in scene units: the primary ray's, and every later segment's.
pub const FIRST_T: u32 = 20;
pub const NEXT_T: u32 = 30;

/// The texture: 64×64 texels, all 7 levels, each level one colour
/// (`LEVEL_RGBA`), so a sample's colour shows the levels it blended.
const SIZE: u32 = 64;
const LEVELS: u8 = 7;
pub const LEVEL_RGBA: [Texel; LEVELS as usize] = [
    0xFF00_00FF,
    0xFF00_80FF,
    0xFF00_FFFF,
    0xFF00_FF00,
    0xFFFF_FF00,
    0xFFFF_0000,
    0xFFFF_00FF,
];
/// The pyramid in flash (built ahead, as a host tool would): level 0 first.
static PYRAMID: [Texel; pyramid_len(SIZE, SIZE, LEVELS)] = {
    let mut texels = [0; pyramid_len(SIZE, SIZE, LEVELS)];
    let (mut level, mut start) = (0, 0);
    while level < LEVELS {
        let end = start + ((SIZE >> level) * (SIZE >> level)) as usize;
        while start < end {
            texels[start] = LEVEL_RGBA[level as usize];
            start += 1;
        }
        level += 1;
    }
    texels
};

/// What the hits at one depth of a camera ray's paths met (depth 0 = the primary hit).
#[derive(Clone, Copy, Default)]
pub struct Depth {
    /// Hits at this depth.
    pub hits: u32,
    /// The first one's lod (I8F8 bits: levels · 256) and filtered texel
    /// (RGBA8, red in the low byte).
    pub lod: i16,
    pub rgba: Texel,
}

/// The result of one camera ray.
pub struct Report {
    pub depths: [Depth; BOUNCES as usize + 1],
    /// Most entries the ray stack held, and continuations it had to drop.
    pub stack_max: usize,
    pub dropped: u32,
}

pub fn run() -> Result<Report, &'static str> {
    // --- set-up (once per camera, scene and texture) ---
    let spread = PixelSpread::from_angle(SPREAD).map_err(|_| "pixel spread")?;
    // A unit square (two triangles) mapped once onto the texture; fixed-point
    // positions (scene units) and UVs (texture repeats).
    let (o, l) = (Coord::ZERO, Coord::ONE);
    let (uo, ul) = (TexCoord::ZERO, TexCoord::ONE);
    let tri = TexTriangle::new(
        [[o, o, o], [l, o, o], [o, l, o]],
        [[uo, uo], [ul, uo], [uo, ul]],
        SIZE,
        SIZE,
    )
    .map_err(|_| "triangle")?;
    let mut entries = [Log2Pb::UNTEXTURED; 2];
    let mut table = PbTable::new(&mut entries);
    table
        .build([Some(tri), Some(tri)], &spread)
        .map_err(|_| "Pb table")?;
    let geometry = Geometry::new(SIZE, SIZE, LEVELS).map_err(|_| "geometry")?;
    let mut sampler = Sampler::wrap(Pyramid::new(geometry, &PYRAMID).map_err(|_| "pyramid")?);

    // --- per hit: pop a path, trace its segment, lod, sample, push its continuations ---
    let mut report = Report {
        depths: [Depth::default(); BOUNCES as usize + 1],
        stack_max: 0,
        dropped: 0,
    };
    let mut stack: RayStack<(), STACK> = RayStack::new();
    stack
        .push(PathState::primary(&spread, 0xFF))
        .map_err(|_| "ray stack")?;
    while let Some(path) = stack.pop() {
        // The accelerator traces the segment; here every ray hits triangle 1.
        let t = if path.depth == 0 { FIRST_T } else { NEXT_T };
        let hit = path.advance(PathLength::from_num(t));
        let Some(lod) = table_lod::<Accurate>(hit.pl, table.get(1).unwrap_or(Log2Pb::UNTEXTURED))
        else {
            continue; // untextured: no texture work
        };
        let (u, v) = (TexCoord::from_bits(3 << 30), TexCoord::from_bits(1 << 30)); // (0.75, 0.25)
        let rgba = sampler.sample(u, v, lod, Mode::Trilinear);
        if let Some(at) = report.depths.get_mut(usize::from(hit.depth)) {
            if at.hits == 0 {
                (at.lod, at.rgba) = (lod.to_bits(), rgba);
            }
            at.hits += 1;
        }
        if hit.depth < BOUNCES {
            for _ in 0..2 {
                // A flat mirror and a flat refractor add no spread (β = 0).
                if stack.push(hit.bounce(Spread::ZERO)).is_err() {
                    report.dropped += 1;
                }
            }
        }
        report.stack_max = report.stack_max.max(stack.len());
    }
    Ok(report)
}
