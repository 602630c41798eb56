//! Budgets of single per-hit calls (run by `scripts/budgets` under QEMU).
//!
//! Each measured function is a `#[no_mangle] #[inline(never)]` wrapper
//! around one library call, called [`N`] times with the pseudo-random inputs
//! of [`raymip_demo_firmware::inputs`], hidden from the optimiser
//! (`black_box`):
//!
//! * `rm_bench_lod`: one table LOD (`log2 Pl − log2 Pb`, rounded);
//! * `rm_bench_cone_lod`: one ray-cone LOD with the normal term;
//! * `rm_bench_lod_fast`, `rm_bench_cone_lod_fast`: the same through the
//!   FAST paths (`table_lod_fast`, `cone_lod_fast`);
//! * `rm_bench_bilinear`: one bilinear sample at the nearest level;
//! * `rm_bench_trilinear`: one trilinear sample (two bilinear levels and the
//!   blend; the LOD always has a fractional part, so both levels are read);
//! * `rm_bench_trilinear_fast`: the same through the FAST tier's wrap
//!   sampler (`Cfg<Wrap, Wrap, Linear, Fast>`: 8-bit positions, exact
//!   corner weights, bound 1.5 LSB);
//! * `rm_bench_f32_*`: the same four stages in f32 (`raymip::float`, libm)
//!   on the same inputs converted to f32 outside the call: hardware FPU on
//!   the Cortex-M4F, soft float on RV32IMAC;
//! * `rm_batch_*`: the batch entry points (slice of hits in, slice of
//!   results out, caller memory), called once with the first 32 and once
//!   with all 64 inputs: the difference over 32 is the steady-state cost
//!   per hit.
//! * `rm_bench_ts_*`: the GPU-style `TextureSampler` (sampler state,
//!   formats, sRGB, BC1 through the texel cache, anisotropic filtering) on
//!   the demo texture's 32×32 geometry, states from
//!   [`raymip_demo_firmware::inputs::sampler_state`] and
//!   [`raymip_demo_firmware::inputs::aniso_state`]. A wrapper serving
//!   several rows is called 64 times per row in a documented order (one
//!   wrapper per signature: identical bodies would be merged by the
//!   compiler into one symbol);
//! * `rm_bench_geomlod` / `rm_batch_geomlod`: `geomlod::Selector::fill`
//!   in discrete and stochastic mode, one instance per call (64 calls per
//!   mode) and 32 / 64 instances per call (per instance = the difference
//!   over 32).
//!
//! `scripts/budgets` counts the instructions executed from each wrapper's
//! entry to its return from the QEMU execution trace (`-d exec,nochain`
//! with one instruction per translation block), on both targets. On RISC-V
//! this binary also reads `minstret` around every fixed-point call (exact
//! under `-icount shift=0`) and prints the call-inclusive counts minus an
//! empty call. The stack each wrapper uses is measured by stack painting.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

use core::hint::black_box as bb;

use fixed::types::{I16F16, U1F31};
use raymip::float::{SamplerF32, cone_lod_f32, table_lod_f32};
use raymip::geomlod::{Depth, InstanceLod, LodMode, RecordsFull, Selector};
use raymip::lod::{
    Lod, cone_lod, cone_lod_batch, cone_lod_fast, cone_lod_fast_batch, table_lod, table_lod_batch,
    table_lod_fast, table_lod_fast_batch,
};
use raymip::log2_fast::NormPl;
use raymip::raystack::{PathLength, Width};
use raymip::table::Log2Pb;
use raymip::texture::address::{ClampToBorder, Mirror, Wrap};
use raymip::texture::kernel::{Accurate, Fast, Linear, Srgb};
use raymip::texture::sampler::aniso::Footprint;
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::{Bc1, Rgb565};
use raymip::texture::storage::format::{ColorSpace, TexelFormat};
use raymip::texture::storage::image::{Image, image_len};
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel};
use raymip::texture::{AddressMode, Cfg, Mode, Sampler, TexCoord};
use raymip_demo_firmware::inputs::{self, N, Rng};
use raymip_demo_firmware::stack;
use raymip_demo_scene::{TEX_LEVELS, TEX_SIZE};
use semihosting::{println, process};

/// Stack bytes painted per measurement.
const PAINT: usize = 2048;

type Tex = Sampler<Pyramid<'static>>;
type TexFast = Sampler<Pyramid<'static>, Cfg<Wrap, Wrap, Linear, Fast>>;
type LodIn = (PathLength, Log2Pb);
type LodNormIn = (NormPl, Log2Pb);
type ConeIn = (Width, I16F16, Option<U1F31>);
type SampleIn = (TexCoord, TexCoord, Lod);
/// The state rows' key: mirror on u, clamp-to-border on v.
type Ts<S, C = Linear> = Sampler<S, Cfg<Mirror, ClampToBorder, C>>;
type Bc1Cache<'a> = TexelCache<Image<'a, Bc1>, 8, 2>;
/// The state rows' key at the FAST tier.
type TsF<S> = Sampler<S, Cfg<Mirror, ClampToBorder, Linear, Fast>>;
/// The wrap rows' key (bias and lod clamp set at run time) at tier `P`.
type Tw<'a, P = Accurate> = Sampler<Pyramid<'a>, Cfg<Wrap, Wrap, Linear, P>>;
type Instances = [(u32, Depth)];

/// One table LOD.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    table_lod(pl, pb)
}

/// One ray-cone LOD with the normal term.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_cone_lod(w: Width, delta: I16F16, n_dot_d: Option<U1F31>) -> Lod {
    cone_lod(w, delta, n_dot_d)
}

/// One FAST table LOD (1024-entry log2 table, no interpolation).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_lod_fast(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    table_lod_fast(pl, pb)
}

/// One FAST ray-cone LOD with the normal term.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_cone_lod_fast(w: Width, delta: I16F16, n_dot_d: Option<U1F31>) -> Lod {
    cone_lod_fast(w, delta, n_dot_d)
}

/// One bilinear sample at the nearest level.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_bilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

/// One trilinear sample.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_trilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One FAST trilinear sample (the FAST tier's wrap sampler).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_trilinear_fast(s: &mut TexFast, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One table LOD in f32.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_f32_lod(pl: f32, log2_pb: f32) -> f32 {
    table_lod_f32(pl, log2_pb)
}

/// One ray-cone LOD with the normal term in f32.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_f32_cone_lod(w: f32, delta: f32, n_dot_d: Option<f32>) -> f32 {
    cone_lod_f32(w, delta, n_dot_d)
}

/// One bilinear sample at the nearest level in f32.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_f32_bilinear(s: &SamplerF32<'_>, u: f32, v: f32, lod: f32) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

/// One trilinear sample in f32.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_f32_trilinear(s: &SamplerF32<'_>, u: f32, v: f32, lod: f32) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// A batch of table LODs.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_lod(hits: &[LodIn], out: &mut [Option<Lod>]) -> usize {
    table_lod_batch(hits, out)
}

/// A batch of ray-cone LODs.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_cone_lod(hits: &[ConeIn], out: &mut [Lod]) -> usize {
    cone_lod_batch(hits, out)
}

/// A batch of FAST table LODs.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_lod_fast(hits: &[LodNormIn], out: &mut [Option<Lod>]) -> usize {
    table_lod_fast_batch(hits, out)
}

/// A batch of FAST ray-cone LODs.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_cone_lod_fast(hits: &[ConeIn], out: &mut [Lod]) -> usize {
    cone_lod_fast_batch(hits, out)
}

/// A batch of bilinear samples at the nearest level.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_bilinear(s: &mut Tex, hits: &[SampleIn], out: &mut [Texel]) -> usize {
    s.sample_batch(hits, Mode::BilinearNearestLevel, out)
}

/// A batch of trilinear samples.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_trilinear(s: &mut Tex, hits: &[SampleIn], out: &mut [Texel]) -> usize {
    s.sample_batch(hits, Mode::Trilinear, out)
}

/// One bilinear sample through `TextureSampler` (RGBA8, state with
/// mirror/border addressing, bias and lod clamp).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_bilinear(s: &mut Ts<Pyramid<'_>>, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

/// One trilinear sample of an RGBA8 pyramid with the state key.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_trilinear(s: &mut Ts<Pyramid<'_>>, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One trilinear sample of the same texels read as sRGB (decoded to
/// linear, filtered, re-encoded).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_srgb(
    s: &mut Ts<Pyramid<'_>, Srgb>,
    u: TexCoord,
    v: TexCoord,
    lod: Lod,
) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One trilinear sample of an RGB565 image (decoded per texel read).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_rgb565(
    s: &mut Ts<Image<'_, Rgb565>>,
    u: TexCoord,
    v: TexCoord,
    lod: Lod,
) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One trilinear sample of a BC1 image through an 8×2-block texel cache,
/// called in pairs: first with the cache emptied by the caller (every
/// block the sample reads is filled, i.e. decoded), then the same sample
/// again (every texel read hits).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_bc1(s: &mut Ts<Bc1Cache<'_>>, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// One anisotropic sample (trilinear probes): called 64 times with at
/// most 2 probes, then 4, then 16 (three samplers, one per cap).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_aniso(
    s: &mut Sampler<Pyramid<'_>>,
    u: TexCoord,
    v: TexCoord,
    fp: &Footprint,
) -> Texel {
    s.sample_aniso(u, v, fp)
}

/// The sampler matrix of issue 20: one wrapper per call, key and tier.
/// The wrap rows (RGBA8, wrap on both axes, lod bias and clamp set:
/// [`inputs::wrap_state`]) have the type of the plain rows, so they call
/// the plain rows' wrappers a second time (a second wrapper of the same
/// type would be merged with the first by the compiler), plus
/// `rm_bench_bilinear_fast` / `rm_batch_*_fast` for the FAST bilinear and
/// batches; `rm_bench_ts_*_fast`: the FAST tier of the `rm_bench_ts_*`
/// rows above (mirror/border key).
macro_rules! sample_wrapper {
    ($(#[$m:meta])* $name:ident, $ty:ty, $mode:expr) => {
        $(#[$m])*
        #[allow(unsafe_code)]
        #[unsafe(no_mangle)]
        #[inline(never)]
        pub fn $name(s: &mut $ty, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
            s.sample(u, v, lod, $mode)
        }
    };
}
sample_wrapper!(
    /// RGBA8 bilinear, wrap, bias and clamp set, FAST.
    rm_bench_bilinear_fast, Tw<'_, Fast>, Mode::BilinearNearestLevel);
sample_wrapper!(
    /// RGBA8 bilinear, mirror/border key, FAST.
    rm_bench_ts_bilinear_fast, TsF<Pyramid<'_>>, Mode::BilinearNearestLevel);
sample_wrapper!(
    /// RGBA8 trilinear, mirror/border key, FAST.
    rm_bench_ts_trilinear_fast, TsF<Pyramid<'_>>, Mode::Trilinear);
sample_wrapper!(
    /// RGB565 trilinear, mirror/border key, FAST.
    rm_bench_ts_rgb565_fast, TsF<Image<'_, Rgb565>>, Mode::Trilinear);
sample_wrapper!(
    /// BC1 trilinear through the texel cache, mirror/border key, FAST
    /// (called in pairs like [`rm_bench_ts_bc1`]).
    rm_bench_ts_bc1_fast, TsF<Bc1Cache<'_>>, Mode::Trilinear);

/// One anisotropic sample at the FAST tier (trilinear probes), called like
/// [`rm_bench_ts_aniso`].
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_ts_aniso_fast(
    s: &mut Tw<'_, Fast>,
    u: TexCoord,
    v: TexCoord,
    fp: &Footprint,
) -> Texel {
    s.sample_aniso(u, v, fp)
}

/// Batches of the wrap rows (32, then 64 hits per call).
macro_rules! batch_wrapper {
    ($(#[$m:meta])* $name:ident, $ty:ty, $mode:expr) => {
        $(#[$m])*
        #[allow(unsafe_code)]
        #[unsafe(no_mangle)]
        #[inline(never)]
        pub fn $name(s: &mut $ty, hits: &[SampleIn], out: &mut [Texel]) -> usize {
            s.sample_batch(hits, $mode, out)
        }
    };
}
batch_wrapper!(
    /// Batch: RGBA8 bilinear, wrap, bias and clamp set, FAST.
    rm_batch_bilinear_fast, Tw<'_, Fast>, Mode::BilinearNearestLevel);
batch_wrapper!(
    /// Batch: RGBA8 trilinear, wrap, bias and clamp set, FAST.
    rm_batch_trilinear_fast, Tw<'_, Fast>, Mode::Trilinear);

/// The instance records of one instance: called 64 times with the
/// discrete selector, then 64 times with the stochastic one.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_geomlod(
    sel: &Selector,
    inst: (u32, Depth),
    out: &mut [InstanceLod],
) -> Result<usize, RecordsFull> {
    sel.fill(core::iter::once(inst), out)
}

/// The instance records of a slice of instances: called with 32 and 64
/// instances, discrete then stochastic.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_batch_geomlod(
    sel: &Selector,
    inst: &Instances,
    out: &mut [InstanceLod],
) -> Result<usize, RecordsFull> {
    sel.fill(inst.iter().copied(), out)
}

/// An empty call (baseline of the `minstret` call-inclusive counts).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_empty(x: u32) -> u32 {
    x
}

/// Retired-instruction counter (RISC-V `minstret`; 0 elsewhere).
#[inline(always)]
fn instret() -> u32 {
    #[cfg(target_arch = "riscv32")]
    {
        riscv::register::minstret::read() as u32
    }
    #[cfg(not(target_arch = "riscv32"))]
    {
        0
    }
}

/// min / sum / max of per-call counts.
#[derive(Clone, Copy)]
struct Stat {
    min: u32,
    sum: u32,
    max: u32,
}

impl Stat {
    const fn new() -> Self {
        Self {
            min: u32::MAX,
            sum: 0,
            max: 0,
        }
    }
    fn add(&mut self, x: u32) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.sum += x;
    }
}

/// Measures one wrapper over `inputs`: `call` makes one call; returns the
/// call-inclusive `minstret` statistics and the painted stack depth.
#[inline(always)]
fn measure<I: Copy>(inputs: &[I], mut call: impl FnMut(I) -> u32) -> (Stat, usize) {
    let mut s = Stat::new();
    let top = stack::sp();
    stack::paint(top, PAINT);
    for &x in inputs {
        let x = bb(x);
        let a = instret();
        let y = call(x);
        let b = instret();
        bb(y);
        s.add(b.wrapping_sub(a));
    }
    (s, stack::used(top, PAINT))
}

/// Ray differentials (feature `raydiff`): the primary set-up, one
/// transfer, a reflection, a refraction, the footprint, its lod and the
/// G-buffer first-hit set-up, each its own wrapper.
#[cfg(feature = "raydiff")]
mod rd {
    use fixed::types::I2F30;
    use raymip::lod::Lod;
    use raymip::raydiff::footprint::RayDiffTriangle;
    use raymip::raydiff::gbuffer::{GSample, first_hit};
    use raymip::raydiff::{DirDiff, Eta, PosDiff, RayDiff, UnitVec};
    use raymip::raystack::PathLength;
    use raymip::texture::sampler::aniso::Footprint;

    /// Primary-ray set-up from the camera axes.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_primary(
        d: UnitVec,
        f: UnitVec,
        r: [DirDiff; 3],
        u: [DirDiff; 3],
    ) -> RayDiff {
        RayDiff::primary(d, f, r, u).0
    }

    /// One transfer to a hit.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_transfer(s: &RayDiff, d: UnitVec, t: PathLength, n: UnitVec) -> RayDiff {
        s.transfer(d, t, n).0
    }

    /// One reflection.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_reflect(s: &RayDiff, d: UnitVec, n: UnitVec, dn: [DirDiff; 3]) -> RayDiff {
        s.reflect(d, n, dn, dn).0
    }

    /// One refraction (η = 1/1.5, cos θₜ = 0.9).
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_refract(s: &RayDiff, d: UnitVec, n: UnitVec, dn: [DirDiff; 3]) -> RayDiff {
        s.refract(
            d,
            n,
            dn,
            dn,
            Eta::from_bits(0x0AAA_AAAB),
            I2F30::from_bits(0x3999_999A),
        )
        .0
    }

    /// The footprint of a transferred state.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_footprint(
        t: &RayDiffTriangle,
        dpx: [PosDiff; 3],
        dpy: [PosDiff; 3],
    ) -> Footprint {
        t.footprint(dpx, dpy)
    }

    /// The lod of a footprint.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_lod(t: &RayDiffTriangle, fp: &Footprint) -> Lod {
        t.lod(fp)
    }

    /// G-buffer first-hit set-up from four neighbours.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_rd_gbuffer(p: &RayDiff, c: &GSample, nb: [Option<&GSample>; 4]) -> RayDiff {
        first_hit(p, c, nb).0
    }
}

/// Environment map (feature `envmap`): the cone lod without and with
/// the pole term, the ray-differential lod (with `raydiff`) and the
/// direction → `(u, v)` mapping, each its own wrapper.
#[cfg(feature = "envmap")]
mod env {
    use raymip::envmap::{EnvMap, direction_uv};
    use raymip::lod::Lod;
    use raymip::raystack::{Spread, UnitVec};
    use raymip::texture::TexCoord;

    /// Cone lod, equator texel (no direction).
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_env_cone(m: &EnvMap, g: Spread) -> Lod {
        m.cone_lod(g, None)
    }

    /// Cone lod with the pole term of the direction.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_env_cone_lat(m: &EnvMap, g: Spread, d: UnitVec) -> Lod {
        m.cone_lod(g, Some(d))
    }

    /// Ray-differential lod with the pole term.
    #[cfg(feature = "raydiff")]
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_env_raydiff(
        m: &EnvMap,
        dx: [raymip::raydiff::DirDiff; 3],
        dy: [raymip::raydiff::DirDiff; 3],
        d: UnitVec,
    ) -> Lod {
        m.raydiff_lod(dx, dy, Some(d))
    }

    /// The lat-long `(u, v)` of a direction.
    #[allow(unsafe_code)]
    #[unsafe(no_mangle)]
    #[inline(never)]
    pub fn rm_bench_env_uv(d: UnitVec) -> (TexCoord, TexCoord) {
        direction_uv(d)
    }
}

/// The environment-map rows (own generator): 64 calls of each
/// `rm_bench_env_*` wrapper on a 2048 × 1024 map.
#[cfg(feature = "envmap")]
#[inline(always)]
fn envmap_rows() {
    let mut rng = Rng(inputs::SEED ^ 0xE0E0);
    let env_in = draw(&mut rng, inputs::envmap);
    let Ok(map) = raymip::envmap::EnvMap::new(2048, 1024) else {
        process::exit(1)
    };
    let map = bb(map);
    measure(&env_in, |(g, ..)| {
        env::rm_bench_env_cone(&map, g).to_bits() as u32
    });
    measure(&env_in, |(g, d, ..)| {
        env::rm_bench_env_cone_lat(&map, g, d).to_bits() as u32
    });
    #[cfg(feature = "raydiff")]
    measure(&env_in, |(_, d, dx, dy)| {
        env::rm_bench_env_raydiff(&map, dx, dy, d).to_bits() as u32
    });
    measure(&env_in, |(_, d, ..)| {
        let (u, v) = env::rm_bench_env_uv(d);
        (u.to_bits() ^ v.to_bits()) as u32
    });
}

/// `N` inputs drawn by `draw`.
fn draw<I: Copy>(rng: &mut Rng, mut draw: impl FnMut(&mut Rng) -> I) -> [I; N] {
    let first = draw(rng);
    let mut out = [first; N];
    for x in out.iter_mut().skip(1) {
        *x = draw(rng);
    }
    out
}

/// The `TextureSampler` and geometric-LOD subjects (built in `main`).
struct Parity<'a> {
    /// RGBA8, [`inputs::sampler_state`], linear.
    rgba: Ts<Pyramid<'a>>,
    /// The same texels read as sRGB, results re-encoded.
    srgb: Ts<Pyramid<'a>, Srgb>,
    /// The demo texture converted to RGB565.
    rgb565: Ts<Image<'a, Rgb565>>,
    /// Pseudo-random BC1 blocks through an 8×2-block texel cache.
    bc1: Ts<Bc1Cache<'a>>,
    /// RGBA8, wrap, at most 2, 4 and 16 probes.
    aniso: [Sampler<Pyramid<'a>>; 3],
    /// The same at the FAST tier.
    aniso_fast: [Tw<'a, Fast>; 3],
    /// RGBA8, wrap, bias and clamp set: ACCURATE, FAST.
    wrap: (Tex, TexFast),
    /// The mirror/border rows at the FAST tier: RGBA8, RGB565, BC1.
    fast: (TsF<Pyramid<'a>>, TsF<Image<'a, Rgb565>>, TsF<Bc1Cache<'a>>),
    /// Discrete and stochastic (`t` = ½) geometric LOD.
    geomlod: [(&'static str, Selector); 2],
}

/// The driver: every measured call happens here (the trace counter ends a
/// call when execution is back inside this function).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
fn rm_budget_driver(
    tex: &mut Tex,
    texfast: &mut TexFast,
    texf: &SamplerF32<'_>,
    par: &mut Parity<'_>,
) {
    let mut rng = Rng(inputs::SEED);
    let empty_in = draw(&mut rng, Rng::next);
    let lod_in = draw(&mut rng, inputs::table_lod);
    let cone_in = draw(&mut rng, inputs::cone_lod);
    let bil_in = draw(&mut rng, inputs::bilinear);
    let tri_in = draw(&mut rng, inputs::trilinear);

    let (empty, _) = measure(&empty_in, rm_bench_empty);
    let (lod, lod_stack) = measure(&lod_in, |(pl, pb)| {
        rm_bench_lod(pl, pb).map_or(0, |l| l.to_bits() as u32)
    });
    let (cone, cone_stack) = measure(&cone_in, |(w, d, c)| {
        rm_bench_cone_lod(w, d, c).to_bits() as u32
    });
    let (lod_fast, lod_fast_stack) = measure(&lod_in, |(pl, pb)| {
        rm_bench_lod_fast(pl, pb).map_or(0, |l| l.to_bits() as u32)
    });
    let (cone_fast, cone_fast_stack) = measure(&cone_in, |(w, d, c)| {
        rm_bench_cone_lod_fast(w, d, c).to_bits() as u32
    });
    let (bil, bil_stack) = measure(&bil_in, |(u, v, lod)| rm_bench_bilinear(tex, u, v, lod));
    let (tri, tri_stack) = measure(&tri_in, |(u, v, lod)| rm_bench_trilinear(tex, u, v, lod));
    let (tri_fast, tri_fast_stack) = measure(&tri_in, |(u, v, lod)| {
        rm_bench_trilinear_fast(texfast, u, v, lod)
    });

    // The same stages in f32 on the same inputs (converted here, outside
    // the counted calls).
    let f = |x: I16F16| x.to_num::<f32>();
    measure(&lod_in, |(pl, pb)| {
        rm_bench_f32_lod(pl.to_num(), f(pb.to_i16f16())).to_bits()
    });
    measure(&cone_in, |(w, d, c)| {
        rm_bench_f32_cone_lod(w.to_num(), f(d), c.map(|c| c.to_num())).to_bits()
    });
    let sf = |(u, v, lod): SampleIn| (u.to_num::<f32>(), v.to_num::<f32>(), lod.to_num::<f32>());
    measure(&bil_in, |x| {
        let (u, v, l) = sf(x);
        rm_bench_f32_bilinear(texf, u, v, l)
    });
    measure(&tri_in, |x| {
        let (u, v, l) = sf(x);
        rm_bench_f32_trilinear(texf, u, v, l)
    });

    // Batches of N/2 and N hits.
    let mut lod_out = [None; N];
    let mut cone_out = [Lod::ZERO; N];
    let mut tex_out = [0; N];
    // The FAST batch reads the normalised Pl a ray-stack entry keeps
    // (`PathState::pl_norm`, made by `advance`): converted here.
    let lod_norm_in = lod_in.map(|(pl, pb)| (NormPl::new(pl), pb));
    for n in [N / 2, N] {
        bb(rm_batch_lod(bb(&lod_in[..n]), &mut lod_out));
        bb(rm_batch_cone_lod(bb(&cone_in[..n]), &mut cone_out));
        bb(rm_batch_lod_fast(bb(&lod_norm_in[..n]), &mut lod_out));
        bb(rm_batch_cone_lod_fast(bb(&cone_in[..n]), &mut cone_out));
        bb(rm_batch_bilinear(tex, bb(&bil_in[..n]), &mut tex_out));
        bb(rm_batch_trilinear(tex, bb(&tri_in[..n]), &mut tex_out));
    }
    bb((&lod_out, &cone_out, &tex_out));

    // TextureSampler: the bilinear/trilinear inputs above; BC1 in pairs
    // (cache emptied here, outside the counted call; then the same sample).
    let aniso_in = draw(&mut rng, inputs::aniso);
    measure(&bil_in, |(u, v, l)| {
        rm_bench_ts_bilinear(&mut par.rgba, u, v, l)
    });
    measure(&tri_in, |(u, v, l)| {
        rm_bench_ts_trilinear(&mut par.rgba, u, v, l)
    });
    measure(&tri_in, |(u, v, l)| {
        rm_bench_ts_srgb(&mut par.srgb, u, v, l)
    });
    measure(&tri_in, |(u, v, l)| {
        rm_bench_ts_rgb565(&mut par.rgb565, u, v, l)
    });
    measure(&tri_in, |(u, v, l)| {
        par.bc1.source_mut().invalidate();
        let a = rm_bench_ts_bc1(&mut par.bc1, u, v, l);
        a ^ rm_bench_ts_bc1(&mut par.bc1, u, v, l)
    });
    for s in &mut par.aniso {
        measure(&aniso_in, |(u, v, fp)| rm_bench_ts_aniso(s, u, v, &fp));
    }
    matrix_rows(par, &bil_in, &tri_in, &aniso_in);

    // Geometric LOD: one instance per call, then 32 and 64 per call.
    let inst: [(u32, Depth); N] = inputs::instances(&mut rng, 0);
    let mut rec = [InstanceLod::default(); 2 * N];
    for (_, sel) in &par.geomlod {
        measure(&inst, |x| {
            rm_bench_geomlod(sel, x, &mut rec).unwrap_or(usize::MAX) as u32
        });
    }
    for (name, sel) in &par.geomlod {
        for n in [N / 2, N] {
            let r = rm_batch_geomlod(sel, bb(&inst[..n]), &mut rec);
            if n == N {
                println!("geomlod {name}: {} records", r.unwrap_or(0));
            }
        }
    }
    bb(&rec);

    #[cfg(feature = "raydiff")]
    raydiff_rows();
    #[cfg(feature = "envmap")]
    envmap_rows();

    if cfg!(target_arch = "riscv32") {
        // Call-inclusive minus the empty call's count.
        let e = empty.min;
        for (name, s) in [
            ("lod", lod),
            ("cone_lod", cone),
            ("lod_fast", lod_fast),
            ("cone_lod_fast", cone_fast),
            ("bilinear", bil),
            ("trilinear", tri),
            ("trilinear_fast", tri_fast),
        ] {
            println!(
                "minstret {name}: min {} mean {} max {} (minus empty call {e})",
                s.min - e,
                (s.sum - N as u32 * e) / N as u32,
                s.max - e
            );
        }
    }
    for (name, bytes) in [
        ("lod", lod_stack),
        ("cone_lod", cone_stack),
        ("lod_fast", lod_fast_stack),
        ("cone_lod_fast", cone_fast_stack),
        ("bilinear", bil_stack),
        ("trilinear", tri_stack),
        ("trilinear_fast", tri_fast_stack),
    ] {
        println!("stack {name}: {bytes} bytes");
    }
}

/// The sampler matrix of issue 20 (after the other rows: no generator
/// draws, their inputs unchanged): the wrap rows (single calls, then
/// batches of 32 and 64 hits), the FAST tier of the mirror/border rows,
/// and anisotropic FAST.
#[inline(always)]
fn matrix_rows(
    par: &mut Parity<'_>,
    bil_in: &[SampleIn; N],
    tri_in: &[SampleIn; N],
    aniso_in: &[(TexCoord, TexCoord, Footprint); N],
) {
    let (wa, wf) = &mut par.wrap;
    measure(bil_in, |(u, v, l)| rm_bench_bilinear(wa, u, v, l));
    measure(tri_in, |(u, v, l)| rm_bench_trilinear(wa, u, v, l));
    measure(bil_in, |(u, v, l)| rm_bench_bilinear_fast(wf, u, v, l));
    measure(tri_in, |(u, v, l)| rm_bench_trilinear_fast(wf, u, v, l));
    let mut out = [0; N];
    for n in [N / 2, N] {
        bb(rm_batch_bilinear(wa, bb(&bil_in[..n]), &mut out));
        bb(rm_batch_trilinear(wa, bb(&tri_in[..n]), &mut out));
        bb(rm_batch_bilinear_fast(wf, bb(&bil_in[..n]), &mut out));
        bb(rm_batch_trilinear_fast(wf, bb(&tri_in[..n]), &mut out));
    }
    bb(&out);
    let (rgba, rgb565, bc1) = &mut par.fast;
    measure(bil_in, |(u, v, l)| rm_bench_ts_bilinear_fast(rgba, u, v, l));
    measure(tri_in, |(u, v, l)| {
        rm_bench_ts_trilinear_fast(rgba, u, v, l)
    });
    measure(tri_in, |(u, v, l)| rm_bench_ts_rgb565_fast(rgb565, u, v, l));
    measure(tri_in, |(u, v, l)| {
        bc1.source_mut().invalidate();
        let a = rm_bench_ts_bc1_fast(bc1, u, v, l);
        a ^ rm_bench_ts_bc1_fast(bc1, u, v, l)
    });
    for s in &mut par.aniso_fast {
        measure(aniso_in, |(u, v, fp)| rm_bench_ts_aniso_fast(s, u, v, &fp));
    }
}

/// The ray-differential rows (own generator: the other rows' inputs are
/// unchanged): 64 calls of each `rm_bench_rd_*` wrapper, and the ray-stack
/// entry size with the feature.
#[cfg(feature = "raydiff")]
#[inline(always)]
fn raydiff_rows() {
    use raymip::raydiff::footprint::RayDiffTriangle;
    use raymip::raydiff::gbuffer::GSample;
    use raymip::table::{Coord, TexTriangle};
    let mut rng = Rng(inputs::SEED ^ 0xD1FF);
    let rd_in = draw(&mut rng, inputs::raydiff);
    let c = |x: i32| Coord::from_bits(i64::from(x) << 32);
    let Ok(tri) = TexTriangle::new(
        [[c(0), c(0), c(0)], [c(4), c(0), c(1)], [c(0), c(3), c(0)]],
        [[c(0), c(0)], [c(2), c(0)], [c(0), c(1)]],
        TEX_SIZE,
        TEX_SIZE,
    ) else {
        process::exit(1)
    };
    let tri = RayDiffTriangle::new(&tri);
    let h = |x: u32| x & 0xFFFF;
    measure(&rd_in, |(s, d, _, n, _)| {
        h(rd::rm_bench_rd_primary(d, n, s.dddx, s.dddy).dddx[0].to_bits() as u32)
    });
    measure(&rd_in, |(s, d, t, n, _)| {
        h(rd::rm_bench_rd_transfer(&s, d, t, n).dodx[0].to_bits() as u32)
    });
    measure(&rd_in, |(s, d, _, n, dn)| {
        h(rd::rm_bench_rd_reflect(&s, d, n, dn).dddx[0].to_bits() as u32)
    });
    measure(&rd_in, |(s, d, _, n, dn)| {
        h(rd::rm_bench_rd_refract(&s, d, n, dn).dddx[0].to_bits() as u32)
    });
    measure(&rd_in, |(s, ..)| {
        h(rd::rm_bench_rd_footprint(&tri, s.dodx, s.dody).x[0].to_bits() as u32)
    });
    let fps = rd_in.map(|(s, ..)| tri.footprint(s.dodx, s.dody));
    measure(&fps, |fp| rd::rm_bench_rd_lod(&tri, &fp).to_bits() as u32);
    let g = rd_in.map(|(s, d, t, n, _)| GSample {
        p: s.dodx,
        n: d,
        t: t.min(PathLength::from_bits(u64::from(n[0].to_bits() as u32))),
    });
    measure(&rd_in, |(s, _, t, n, _)| {
        let cen = GSample { p: s.dody, n, t };
        let i = (t.to_bits() as usize) % (N - 4);
        h(rd::rm_bench_rd_gbuffer(
            &s,
            &cen,
            [
                Some(&g[i]),
                Some(&g[i + 1]),
                Some(&g[i + 2]),
                Some(&g[i + 3]),
            ],
        )
        .dodx[0]
            .to_bits() as u32)
    });
    println!(
        "path state raydiff: {} bytes",
        core::mem::size_of::<raymip::raystack::PathState>()
    );
}

/// Bytes of the RGB565 and BC1 images (demo texture geometry).
const RGB565_LEN: usize = image_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS, TexelFormat::Rgb565);
const BC1_LEN: usize = image_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS, TexelFormat::Bc1);

/// The `TextureSampler` and geometric-LOD subjects over the demo texture
/// `p` (geometry `g`), `rgb565` (its texels converted) and `bc1` (its
/// blocks).
fn parity<'a>(
    g: Geometry,
    p: Pyramid<'static>,
    rgb565: &'a [u8],
    bc1: &'a [u8],
) -> Option<Parity<'a>> {
    let state = inputs::sampler_state()?;
    let rgb565 = Image::typed(g, ColorSpace::Linear, rgb565).ok()?;
    let bc1 = Image::typed(g, ColorSpace::Linear, bc1).ok()?;
    let aniso = |n| Sampler::with_state(p, inputs::aniso_state(n)?).ok();
    let anisof = |n| Sampler::with_state(p, inputs::aniso_state(n)?).ok();
    let wrap = inputs::wrap_state()?;
    Some(Parity {
        rgba: Sampler::with_state(p, state).ok()?,
        srgb: Sampler::with_state(p, state).ok()?,
        rgb565: Sampler::with_state(rgb565, state).ok()?,
        bc1: Sampler::with_state(TexelCache::new(bc1), state).ok()?,
        aniso: [aniso(2)?, aniso(4)?, aniso(16)?],
        aniso_fast: [anisof(2)?, anisof(4)?, anisof(16)?],
        wrap: (
            Sampler::with_state(p, wrap).ok()?,
            Sampler::with_state(p, wrap).ok()?,
        ),
        fast: (
            Sampler::with_state(p, state).ok()?,
            Sampler::with_state(rgb565, state).ok()?,
            Sampler::with_state(TexelCache::new(bc1), state).ok()?,
        ),
        geomlod: [
            ("discrete", inputs::selector(LodMode::Discrete)?),
            (
                "stochastic",
                inputs::selector(LodMode::Stochastic(inputs::TRANSITION))?,
            ),
        ],
    })
}

raymip_demo_entry::main! {
    let Some(g) = raymip_demo_scene::tex_geometry() else {
        process::exit(1)
    };
    let Ok(p) = Pyramid::new(g, &raymip_demo_scene::TEX0) else {
        process::exit(1)
    };
    let Some(texf) = SamplerF32::new(g, &raymip_demo_scene::TEX0, AddressMode::Wrap) else {
        process::exit(1)
    };
    let mut tex = Sampler::wrap(p);
    let bc1: [u8; BC1_LEN] = inputs::bytes(&mut Rng(inputs::SEED ^ 0xBC1));
    let mut rgb565 = [0u8; RGB565_LEN];
    for (b, &t) in rgb565
        .chunks_exact_mut(2)
        .zip(raymip_demo_scene::TEX0.iter())
    {
        b.copy_from_slice(&(TexelFormat::Rgb565.encode(t) as u16).to_le_bytes());
    }
    let Some(mut par) = parity(g, p, &rgb565, &bc1) else {
        process::exit(1)
    };
    let mut texfast = Sampler::new(p);
    rm_budget_driver(&mut tex, &mut texfast, &texf, &mut par);
    process::exit(0)
}
