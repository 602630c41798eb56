//! The sampler-matrix and ray-differential probes in
//! one place for every counter that times them: the QEMU instruction traces
//! of `src/bin/budget.rs` (`scripts/budgets`) and the PicoRV32 cycle
//! counters of `src/bin/cycles_matrix.rs` (`scripts/softcore`).
//!
//! * the measured wrappers: each a `#[no_mangle] #[inline(never)]` function
//!   around one library call (`rm_bench_*` one call, `rm_batch_*` a
//!   batch), the symbols `scripts/budgets.py` finds in the traces;
//! * their subjects ([`Images`], [`Subjects`]: the demo texture as RGBA8,
//!   RGB565 and BC1 behind the sampler keys of the matrix);
//! * the calls of every row in one order ([`sampler_rows`],
//!   [`raydiff_rows`]) on the inputs of [`crate::inputs`], through a
//!   [`Meter`] that counts each call its own way and names it by the row
//!   keys of `scripts/budgets.py` (`MATRIX_ROWS`, `RD_ROWS`).
//!
//! The wrappers use `#[unsafe(no_mangle)]` (a stable symbol name for the
//! traces; no other unsafe code), each with `allow(unsafe_code)`.

use core::hint::black_box as bb;

use raymip::texture::address::{ClampToBorder, Mirror, Wrap};
use raymip::texture::kernel::{Linear, Srgb};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::{Bc1, ColorSpace, Rgb565, TexelFormat};
use raymip::texture::storage::image::{Image, Pow2Rgb565, image_len};
use raymip::texture::storage::mip::{Geometry, Texel};
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::texture::{Cfg, Mode, NoStats, Sampler};
use raymip::units::{Accurate, Fast, Footprint, Lod, TexCoord};
use raymip_demo_scene::{TEX_LEVELS, TEX_SIZE};

use crate::inputs::{self, N, XorShift32};

/// The plain sampler: RGBA8 power-of-two pyramid (direct level views),
/// wrap, ACCURATE, no fetch statistics (the matrix's keys count none: a
/// firmware that reads no statistics).
pub type Tex = Sampler<Pow2Pyramid<'static>, Cfg<Wrap, Wrap, Linear, Accurate, NoStats>>;
/// The plain sampler at the FAST tier.
pub type TexFast = Sampler<Pow2Pyramid<'static>, Cfg<Wrap, Wrap, Linear, Fast, NoStats>>;
/// One bilinear or trilinear input: `u`, `v`, lod.
pub type SampleIn = (TexCoord, TexCoord, Lod);
/// One anisotropic input: `u`, `v`, footprint.
pub type AnisoIn = (TexCoord, TexCoord, Footprint);
/// The state rows' key: mirror on u, clamp-to-border on v.
pub type Ts<S, C = Linear> = Sampler<S, Cfg<Mirror, ClampToBorder, C, Accurate, NoStats>>;
/// The BC1 image behind an 8×2-block texel cache.
pub type Bc1Cache<'a> = TexelCache<Image<'a, Bc1>, 8, 2>;
/// The state rows' key at the FAST tier.
pub type TsF<S> = Sampler<S, Cfg<Mirror, ClampToBorder, Linear, Fast, NoStats>>;
/// The wrap key with fetch statistics (`FetchStats`, the default key's
/// counting): the matrix's counted row.
pub type TexCounted<'a> = Sampler<Pow2Pyramid<'a>, Cfg<Wrap>>;
/// The wrap rows' key (bias and lod clamp set at run time) at tier `P`.
pub type Tw<'a, P = Accurate> = Sampler<Pow2Pyramid<'a>, Cfg<Wrap, Wrap, Linear, P, NoStats>>;

/// The measured wrappers and the calls the budget binary makes of each:
/// `scripts/budget-rows.txt`, which `scripts/budgets.py` reads too.
pub const ROWS: &str = include_str!("../../../scripts/budget-rows.txt");

/// Whether a line of [`ROWS`] names the wrapper `name` (`name ;` at its
/// start).
#[must_use]
pub const fn listed(name: &str) -> bool {
    let (rows, name) = (ROWS.as_bytes(), name.as_bytes());
    let mut line = 0;
    while line < rows.len() {
        let mut j = 0;
        while j < name.len() && line + j < rows.len() && rows[line + j] == name[j] {
            j += 1;
        }
        let end = line + j;
        if j == name.len() && end + 1 < rows.len() && rows[end] == b' ' && rows[end + 1] == b';' {
            return true;
        }
        while line < rows.len() && rows[line] != b'\n' {
            line += 1;
        }
        line += 1;
    }
    false
}

/// A measured wrapper: the function, public, with a stable symbol name for
/// the traces (`no_mangle`) and never inlined; a wrapper that is not a row
/// of [`ROWS`] does not compile.
#[macro_export]
macro_rules! probe {
    ($(#[$m:meta])* fn $name:ident($($a:ident: $t:ty),*) -> $ret:ty $body:block) => {
        $(#[$m])*
        #[allow(unsafe_code)]
        #[unsafe(no_mangle)]
        #[inline(never)]
        pub fn $name($($a: $t),*) -> $ret $body
        const _: () = assert!(
            $crate::probes::listed(stringify!($name)),
            concat!(stringify!($name), " is not a row of scripts/budget-rows.txt")
        );
    };
}

/// One sample of `mode` through a sampler of type `ty`.
macro_rules! sample_wrapper {
    ($(#[$m:meta])* $name:ident, $ty:ty, $mode:expr) => {
        probe!($(#[$m])* fn $name(s: &mut $ty, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
            s.sample(u, v, lod, $mode)
        });
    };
}

/// A batch of samples of `mode` through a sampler of type `ty`.
macro_rules! batch_wrapper {
    ($(#[$m:meta])* $name:ident, $ty:ty, $mode:expr) => {
        probe!($(#[$m])* fn $name(s: &mut $ty, hits: &[SampleIn], out: &mut [Texel]) -> usize {
            s.sample_batch(hits, $mode, out)
        });
    };
}

/// One anisotropic sample through a sampler of type `ty`.
macro_rules! aniso_wrapper {
    ($(#[$m:meta])* $name:ident, $ty:ty) => {
        probe!($(#[$m])* fn $name(s: &mut $ty, u: TexCoord, v: TexCoord, fp: &Footprint) -> Texel {
            s.sample_aniso(u, v, fp)
        });
    };
}

sample_wrapper!(
    /// One bilinear sample at the nearest level.
    rm_bench_bilinear, Tex, Mode::BilinearNearestLevel);

sample_wrapper!(
    /// One trilinear sample.
    rm_bench_trilinear, Tex, Mode::Trilinear);

sample_wrapper!(
    /// One FAST trilinear sample (the FAST tier's wrap sampler).
    rm_bench_trilinear_fast, TexFast, Mode::Trilinear);

batch_wrapper!(
    /// A batch of bilinear samples at the nearest level.
    rm_batch_bilinear, Tex, Mode::BilinearNearestLevel);

batch_wrapper!(
    /// A batch of trilinear samples.
    rm_batch_trilinear, Tex, Mode::Trilinear);

sample_wrapper!(
    /// One bilinear sample with the state key (RGBA8, mirror/border
    /// addressing, bias and lod clamp).
    rm_bench_ts_bilinear, Ts<Pow2Pyramid<'_>>, Mode::BilinearNearestLevel);

sample_wrapper!(
    /// One trilinear sample of an RGBA8 pyramid with the state key.
    rm_bench_ts_trilinear, Ts<Pow2Pyramid<'_>>, Mode::Trilinear);

sample_wrapper!(
    /// One trilinear sample of the same texels read as sRGB (decoded to
    /// linear, filtered, re-encoded).
    rm_bench_ts_srgb, Ts<Pow2Pyramid<'_>, Srgb>, Mode::Trilinear);

sample_wrapper!(
    /// One trilinear sample of an RGB565 image through its 16-bit level
    /// views (each texel of a footprint expanded once).
    rm_bench_ts_rgb565, Ts<Pow2Rgb565<'_>>, Mode::Trilinear);

sample_wrapper!(
    /// One trilinear sample of a BC1 image through an 8×2-block texel cache,
    /// called in pairs: first with the cache emptied by the caller (every
    /// block the sample reads is filled, i.e. decoded), then the same sample
    /// again (every texel read hits).
    rm_bench_ts_bc1, Ts<Bc1Cache<'_>>, Mode::Trilinear);

aniso_wrapper!(
    /// One anisotropic sample (trilinear probes): called 64 times with at
    /// most 2 probes, then 4, then 16 (three samplers, one per cap).
    rm_bench_ts_aniso, Tw<'_>);

// The sampler matrix: one wrapper per call, key and tier. The wrap rows
// (RGBA8, wrap on both axes, lod bias and clamp set:
// `inputs::wrap_state`) have the type of the plain rows, so they call the
// plain rows' wrappers a second time (a second wrapper of the same type
// would be merged with the first by the compiler), plus
// `rm_bench_bilinear_fast` / `rm_batch_*_fast` for the FAST bilinear and
// batches; `rm_bench_ts_*_fast`: the FAST tier of the `rm_bench_ts_*`
// rows above (mirror/border key).
sample_wrapper!(
    /// RGBA8 bilinear, wrap, bias and clamp set, FAST.
    rm_bench_bilinear_fast, Tw<'_, Fast>, Mode::BilinearNearestLevel);
sample_wrapper!(
    /// RGBA8 trilinear, wrap, bias and clamp set, ACCURATE, counting its
    /// texel reads (`FetchStats`).
    rm_bench_trilinear_counted, TexCounted<'_>, Mode::Trilinear);
sample_wrapper!(
    /// RGBA8 bilinear, mirror/border key, FAST.
    rm_bench_ts_bilinear_fast, TsF<Pow2Pyramid<'_>>, Mode::BilinearNearestLevel);
sample_wrapper!(
    /// RGBA8 trilinear, mirror/border key, FAST.
    rm_bench_ts_trilinear_fast, TsF<Pow2Pyramid<'_>>, Mode::Trilinear);
sample_wrapper!(
    /// RGB565 trilinear, mirror/border key, FAST.
    rm_bench_ts_rgb565_fast, TsF<Pow2Rgb565<'_>>, Mode::Trilinear);
sample_wrapper!(
    /// BC1 trilinear through the texel cache, mirror/border key, FAST
    /// (called in pairs like [`rm_bench_ts_bc1`]).
    rm_bench_ts_bc1_fast, TsF<Bc1Cache<'_>>, Mode::Trilinear);

aniso_wrapper!(
    /// One anisotropic sample at the FAST tier (trilinear probes), called like
    /// [`rm_bench_ts_aniso`].
    rm_bench_ts_aniso_fast, Tw<'_, Fast>);

// Batches of the wrap rows (32, then 64 hits per call).
batch_wrapper!(
    /// Batch: RGBA8 bilinear, wrap, bias and clamp set, FAST.
    rm_batch_bilinear_fast, Tw<'_, Fast>, Mode::BilinearNearestLevel);
batch_wrapper!(
    /// Batch: RGBA8 trilinear, wrap, bias and clamp set, FAST.
    rm_batch_trilinear_fast, Tw<'_, Fast>, Mode::Trilinear);

/// Bytes of the RGB565 image (demo texture geometry).
pub const RGB565_LEN: usize = image_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS, TexelFormat::Rgb565);
/// Bytes of the BC1 image (demo texture geometry).
pub const BC1_LEN: usize = image_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS, TexelFormat::Bc1);

/// The stored texels of the RGB565 and BC1 rows.
pub struct Images {
    /// The demo texture's texels converted to RGB565 (little-endian).
    pub rgb565: [u8; RGB565_LEN],
    /// Pseudo-random BC1 blocks (seed `SEED ^ 0xBC1`).
    pub bc1: [u8; BC1_LEN],
}

impl Images {
    /// The images of the demo texture.
    #[must_use]
    pub fn new() -> Self {
        let bc1 = inputs::bytes(&mut XorShift32(inputs::SEED ^ 0xBC1));
        let mut rgb565 = [0u8; RGB565_LEN];
        for (b, &t) in rgb565
            .chunks_exact_mut(2)
            .zip(raymip_demo_scene::TEX0.iter())
        {
            b.copy_from_slice(&(TexelFormat::Rgb565.encode(t) as u16).to_le_bytes());
        }
        Self { rgb565, bc1 }
    }
}

impl Default for Images {
    fn default() -> Self {
        Self::new()
    }
}

/// The samplers of the state-key (`Ts`) and matrix rows (built by
/// [`Subjects::new`]).
pub struct Subjects<'a> {
    /// RGBA8, [`inputs::sampler_state`], linear.
    pub rgba: Ts<Pow2Pyramid<'a>>,
    /// The same texels read as sRGB, results re-encoded.
    pub srgb: Ts<Pow2Pyramid<'a>, Srgb>,
    /// The demo texture converted to RGB565 (its 16-bit level views).
    pub rgb565: Ts<Pow2Rgb565<'a>>,
    /// Pseudo-random BC1 blocks through an 8×2-block texel cache.
    pub bc1: Ts<Bc1Cache<'a>>,
    /// RGBA8, wrap, at most 2, 4 and 16 probes.
    pub aniso: [Tw<'a>; 3],
    /// The same at the FAST tier.
    pub aniso_fast: [Tw<'a, Fast>; 3],
    /// RGBA8, wrap, bias and clamp set: ACCURATE, FAST (no statistics),
    /// ACCURATE counting its reads.
    pub wrap: (Tex, TexFast, TexCounted<'a>),
    /// The mirror/border rows at the FAST tier: RGBA8, RGB565, BC1.
    pub fast: (TsF<Pow2Pyramid<'a>>, TsF<Pow2Rgb565<'a>>, TsF<Bc1Cache<'a>>),
}

impl<'a> Subjects<'a> {
    /// The subjects over the demo texture `p` (geometry `g`) and `images`
    /// (`None` cannot happen with the demo texture and the states of
    /// [`inputs`]).
    #[must_use]
    pub fn new(g: Geometry, p: Pow2Pyramid<'static>, images: &'a Images) -> Option<Self> {
        let state = inputs::sampler_state()?;
        let rgb565 = Image::<Rgb565>::typed(g, ColorSpace::Linear, &images.rgb565).ok()?;
        let rgb565 = Pow2Rgb565::new(rgb565).ok()?;
        let bc1 = Image::typed(g, ColorSpace::Linear, &images.bc1).ok()?;
        let aniso = |n| Sampler::with_state(p, inputs::aniso_state(n)?).ok();
        let anisof = |n| Sampler::with_state(p, inputs::aniso_state(n)?).ok();
        let wrap = inputs::wrap_state()?;
        Some(Self {
            rgba: Sampler::with_state(p, state).ok()?,
            srgb: Sampler::with_state(p, state).ok()?,
            rgb565: Sampler::with_state(rgb565, state).ok()?,
            bc1: Sampler::with_state(TexelCache::new(bc1), state).ok()?,
            aniso: [aniso(2)?, aniso(4)?, aniso(16)?],
            aniso_fast: [anisof(2)?, anisof(4)?, anisof(16)?],
            wrap: (
                Sampler::with_state(p, wrap).ok()?,
                Sampler::with_state(p, wrap).ok()?,
                Sampler::with_state(p, wrap).ok()?,
            ),
            fast: (
                Sampler::with_state(p, state).ok()?,
                Sampler::with_state(rgb565, state).ok()?,
                Sampler::with_state(TexelCache::new(bc1), state).ok()?,
            ),
        })
    }
}

/// How the calls of a row are counted: each implementation times the
/// wrapper calls its own way (a QEMU trace sees them by symbol, a soft core
/// reads its counters around each) and keys its results by row.
pub trait Meter {
    /// The row `key`: `call` once per input of `xs`, each call counted.
    fn row<I: Copy>(&mut self, key: &str, xs: &[I; N], call: impl FnMut(I) -> u32);

    /// The rows `keys[0]` and `keys[1]`: per input of `xs`, `prepare` (not
    /// counted), then `call` twice on the same input, the first call
    /// counted under `keys[0]`, the second under `keys[1]`.
    fn pairs<S, I: Copy>(
        &mut self,
        keys: [&str; 2],
        s: &mut S,
        xs: &[I; N],
        prepare: impl FnMut(&mut S),
        call: impl FnMut(&mut S, I) -> u32,
    );

    /// The batch row `key`: `call(n)` once with `n` = 32, then with 64.
    fn batch(&mut self, key: &str, call: impl FnMut(usize) -> usize);
}

/// The sampler rows of `s`, in this order: the state-key rows
/// (mirror u / border v, ACCURATE: RGBA8 bilinear and trilinear, sRGB,
/// RGB565, BC1 fill/hit pairs, anisotropic 2×, 4×, 16×), then the rest of
/// the matrix: the wrap rows (single calls, then batches of 32 and 64
/// hits), the FAST tier of the mirror/border rows, anisotropic FAST and
/// the wrap trilinear row with fetch statistics. Keys: `scripts/budgets.py` `MATRIX_ROWS` (batches: the key of the
/// single-call row). The inputs are drawn by the caller (the budgets' order).
#[inline(always)]
pub fn sampler_rows<M: Meter>(
    m: &mut M,
    s: &mut Subjects<'_>,
    bil_in: &[SampleIn; N],
    tri_in: &[SampleIn; N],
    aniso_in: &[AnisoIn; N],
) {
    // `m.row(key, inputs, ..)` of one wrapper call per input.
    macro_rules! rows {
        ($($key:literal, $inputs:expr, $wrapper:ident($s:expr);)+) => {
            $(m.row($key, $inputs, |(u, v, l)| $wrapper($s, u, v, l));)+
        };
    }
    rows! {
        "ts_bil", bil_in, rm_bench_ts_bilinear(&mut s.rgba);
        "ts_tri", tri_in, rm_bench_ts_trilinear(&mut s.rgba);
        "ts_srgb", tri_in, rm_bench_ts_srgb(&mut s.srgb);
        "ts_565", tri_in, rm_bench_ts_rgb565(&mut s.rgb565);
    }
    m.pairs(
        ["ts_bc1_fill", "ts_bc1_hit"],
        &mut s.bc1,
        tri_in,
        |c| c.source_mut().invalidate(),
        |c, (u, v, l)| rm_bench_ts_bc1(c, u, v, l),
    );
    for (key, a) in ["an2", "an4", "an16"].into_iter().zip(&mut s.aniso) {
        m.row(key, aniso_in, |(u, v, fp)| rm_bench_ts_aniso(a, u, v, &fp));
    }

    let (wa, wf, wc) = &mut s.wrap;
    rows! {
        "tw_bil", bil_in, rm_bench_bilinear(wa);
        "tw_tri", tri_in, rm_bench_trilinear(wa);
        "tw_bil_f", bil_in, rm_bench_bilinear_fast(wf);
        "tw_tri_f", tri_in, rm_bench_trilinear_fast(wf);
    }
    let mut out = [0; N];
    // `m.batch(key, ..)` of one wrapper call on the first `n` inputs.
    macro_rules! batches {
        ($($key:literal, $inputs:expr, $wrapper:ident($s:expr);)+) => {
            $(m.batch($key, |n| $wrapper($s, bb(&$inputs[..n]), &mut out));)+
        };
    }
    batches! {
        "tw_bil", bil_in, rm_batch_bilinear(wa);
        "tw_tri", tri_in, rm_batch_trilinear(wa);
        "tw_bil_f", bil_in, rm_batch_bilinear_fast(wf);
        "tw_tri_f", tri_in, rm_batch_trilinear_fast(wf);
    }
    bb(&out);

    let (rgba, rgb565, bc1) = &mut s.fast;
    rows! {
        "ts_bil_f", bil_in, rm_bench_ts_bilinear_fast(rgba);
        "ts_tri_f", tri_in, rm_bench_ts_trilinear_fast(rgba);
        "ts_565_f", tri_in, rm_bench_ts_rgb565_fast(rgb565);
    }
    m.pairs(
        ["ts_bc1_fill_f", "ts_bc1_hit_f"],
        bc1,
        tri_in,
        |c| c.source_mut().invalidate(),
        |c, (u, v, l)| rm_bench_ts_bc1_fast(c, u, v, l),
    );
    for (key, a) in ["an2_f", "an4_f", "an16_f"]
        .into_iter()
        .zip(&mut s.aniso_fast)
    {
        m.row(key, aniso_in, |(u, v, fp)| {
            rm_bench_ts_aniso_fast(a, u, v, &fp)
        });
    }
    rows! {
        "tw_tri_n", tri_in, rm_bench_trilinear_counted(wc);
    }
}

/// Ray differentials (feature `raydiff`): the primary set-up, one
/// transfer, a reflection, a refraction, the footprint, its lod and the
/// G-buffer first-hit set-up, each its own wrapper.
#[cfg(feature = "raydiff")]
pub mod rd {
    use fixed::types::{I2F30, I4F28};
    use raymip::lod::raydiff::{RayDiffFootprint, RayDiffTriangle};
    use raymip::path::raydiff::gbuffer::{GSample, GSides, first_hit};
    use raymip::path::raydiff::{DirDiff, Eta, RayDiff};
    use raymip::units::{Lod, PathLength, UnitVec};

    probe! {
        /// Primary-ray set-up from the camera axes.
        fn rm_bench_rd_primary(d: UnitVec, f: UnitVec, r: DirDiff, u: DirDiff) -> RayDiff {
            RayDiff::primary(d, f, r, u)
        }
    }

    probe! {
        /// One transfer to a hit (in place).
        fn rm_bench_rd_transfer(s: &mut RayDiff, d: UnitVec, t: PathLength, n: UnitVec) -> () {
            s.transfer(d, t, n);
        }
    }

    probe! {
        /// One reflection (in place).
        fn rm_bench_rd_reflect(s: &mut RayDiff, d: UnitVec, n: UnitVec, dn: DirDiff) -> () {
            s.reflect(d, n, [dn, dn]);
        }
    }

    probe! {
        /// One refraction (η = 1/1.5, cos θₜ = 0.9; in place).
        fn rm_bench_rd_refract(s: &mut RayDiff, d: UnitVec, n: UnitVec, dn: DirDiff) -> () {
            s.refract(
                d,
                n,
                [dn, dn],
                Eta::from_fixed(I4F28::from_bits(0x0AAA_AAAB)),
                I2F30::from_bits(0x3999_999A),
            );
        }
    }

    probe! {
        /// The footprint of a transferred state.
        fn rm_bench_rd_footprint(t: &RayDiffTriangle, s: &RayDiff) -> RayDiffFootprint {
            t.footprint(s)
        }
    }

    probe! {
        /// The lod of a footprint.
        fn rm_bench_rd_lod(fp: &RayDiffFootprint) -> Lod {
            fp.lod()
        }
    }

    probe! {
        /// G-buffer first-hit set-up from four neighbours (in place; a
        /// buffer at 2⁻²⁴ scene units).
        fn rm_bench_rd_gbuffer(s: &mut RayDiff, c: &GSample, nb: [Option<&GSample>; 4]) -> () {
            let _ = first_hit(s, c, nb, -24);
        }
    }

    probe! {
        /// The normal differentials of a G-buffer first hit's chosen sides
        /// (for a reflection or refraction there).
        fn rm_bench_rd_gbuffer_normals(sides: &GSides) -> [DirDiff; 2] {
            sides.normal_diffs()
        }
    }
}

/// The ray-differential rows (feature `raydiff`; own generator, seed
/// `SEED ^ 0xD1FF`, so the other rows' inputs are unchanged): 64 calls of
/// each `rm_bench_rd_*` wrapper on [`inputs::raydiff`], the footprint and
/// lod on one 4 × 3 triangle of the demo texture size. Keys:
/// `scripts/budgets.py` `RD_ROWS`. `None` cannot happen (the triangle is
/// valid).
#[cfg(feature = "raydiff")]
#[inline(always)]
pub fn raydiff_rows<M: Meter>(m: &mut M) -> Option<()> {
    use raymip::lod::raydiff::RayDiffTriangle;
    use raymip::path::raydiff::gbuffer::GSample;
    use raymip::setup::table::TexTriangle;
    use raymip::units::Coord;
    let mut rng = XorShift32(inputs::SEED ^ 0xD1FF);
    let rd_in: [inputs::RayDiffIn; N] = core::array::from_fn(|_| inputs::raydiff(&mut rng));
    let c = |x: i32| Coord::from_bits(i64::from(x) << 32);
    let t = |x: i32| TexCoord::from_bits(i64::from(x) << 32);
    let tri = TexTriangle::new(
        [[c(0), c(0), c(0)], [c(4), c(0), c(1)], [c(0), c(3), c(0)]],
        [[t(0), t(0)], [t(2), t(0)], [t(0), t(1)]],
        TEX_SIZE,
        TEX_SIZE,
    )
    .ok()?;
    let tri = RayDiffTriangle::new(&tri);
    // Each row's arguments are made before the count (the primary
    // set-up's taken from the state, the G-buffer's centre sample and
    // neighbours), and each result is only kept (`black_box`): the counters
    // hold the wrapper call alone.
    let prim = rd_in.map(|(s, d, _, n, _)| (d, n, s.ddx(), s.ddy()));
    m.row("rd_primary", &prim, |(d, n, r, u)| {
        bb(rd::rm_bench_rd_primary(d, n, r, u));
        0
    });
    // The in-place calls read their input by reference: only the state
    // they change is copied in the count (a fresh one per call).
    let rd_ref = rd_in.each_ref();
    m.row("rd_transfer", &rd_ref, |&(mut s, d, t, n, _)| {
        rd::rm_bench_rd_transfer(&mut s, d, t, n);
        bb(&mut s);
        0
    });
    m.row("rd_reflect", &rd_ref, |&(mut s, d, _, n, dn)| {
        rd::rm_bench_rd_reflect(&mut s, d, n, dn);
        bb(&mut s);
        0
    });
    m.row("rd_refract", &rd_ref, |&(mut s, d, _, n, dn)| {
        rd::rm_bench_rd_refract(&mut s, d, n, dn);
        bb(&mut s);
        0
    });
    m.row("rd_footprint", &rd_in, |(s, ..)| {
        bb(rd::rm_bench_rd_footprint(&tri, &s));
        0
    });
    let fps = rd_in.map(|(s, ..)| tri.footprint(&s));
    m.row("rd_lod", &fps, |fp| {
        bb(rd::rm_bench_rd_lod(&fp));
        0
    });
    // G-buffer samples at 2⁻²⁴ scene units: positions from the states'
    // ∂O mantissas (below 2²⁹), distances from the hit distances.
    let g = rd_in.map(|(s, d, t, n, _)| GSample {
        p: s.dox().parts().0.map(|x| x >> 2),
        n: d,
        t: ((t.to_bits() >> 8) as u32).min(n[0].to_bits() as u32),
    });
    let gb = rd_in.map(|(s, _, t, n, _)| {
        let cen = GSample {
            p: s.doy().parts().0.map(|x| x >> 2),
            n,
            t: (t.to_bits() >> 8) as u32,
        };
        let i = (t.to_bits() as usize) % (N - 4);
        (s, cen, [i, i + 1, i + 2, i + 3].map(|j| Some(&g[j])))
    });
    m.row("rd_gbuffer", &gb.each_ref(), |&(mut s, ref cen, nb)| {
        rd::rm_bench_rd_gbuffer(&mut s, cen, nb);
        bb(&mut s);
        0
    });
    let sides = gb.each_ref().map(|(s, cen, nb)| {
        raymip::path::raydiff::gbuffer::first_hit(&mut s.clone(), cen, *nb, -24)
    });
    m.row("rd_gbuffer_normals", &sides.each_ref(), |sd| {
        bb(rd::rm_bench_rd_gbuffer_normals(sd));
        0
    });
    Some(())
}
