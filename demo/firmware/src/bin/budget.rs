//! Budgets of single per-hit calls (run by `scripts/budgets` under QEMU).
//!
//! Each measured function is a `#[no_mangle] #[inline(never)]` wrapper
//! ([`probe!`], a row of `scripts/budget-rows.txt` with its number of
//! calls) around one library call, called [`N`] times with the pseudo-random inputs
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
//! * `rm_bench_f32_*`: the same four stages in f32 (`raymip::baseline_f32`, libm)
//!   on the same inputs converted to f32 outside the call: hardware FPU on
//!   the Cortex-M4F, soft float on RV32IMAC;
//! * `rm_batch_*`: the batch entry points (slice of hits in, slice of
//!   results out, caller memory), called once with the first 32 and once
//!   with all 64 inputs: the difference over 32 is the steady-state cost
//!   per hit.
//! * `rm_bench_ts_*`: the GPU-style `Sampler` with a `SamplerState`
//!   (address modes, formats, sRGB, BC1 through the texel cache,
//!   anisotropic filtering) on
//!   the demo texture's 32×32 geometry, states from
//!   [`raymip_demo_firmware::inputs::sampler_state`] and
//!   [`raymip_demo_firmware::inputs::aniso_state`]. A wrapper serving
//!   several rows is called 64 times per row in a documented order (one
//!   wrapper per signature: identical bodies would be merged by the
//!   compiler into one symbol);
//! * `rm_bench_geomlod` / `rm_batch_geomlod`: `geomlod::Selector::fill`
//!   in discrete and stochastic mode, one instance per call (64 calls per
//!   mode) and 32 / 64 instances per call (per instance = the difference
//!   over 32);
//! * `rm_bench_rd_*` (feature `raydiff`): the ray-differential stages.
//!
//! The sampler wrappers (`rm_bench_bilinear`, `rm_bench_trilinear*`,
//! `rm_batch_bilinear`, `rm_batch_trilinear`, `rm_bench_ts_*`, the matrix's
//! `*_fast`), the ray-differential wrappers, their subjects and the order
//! of their calls live in [`raymip_demo_firmware::probes`], shared with the
//! soft core's cycle counts (`src/bin/cycles_matrix.rs`).
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
use raymip::baseline_f32::{SamplerF32, cone_lod_f32, table_lod_f32};
use raymip::geomlod::{InstanceLod, LodMode, RecordsFull, Selector};
use raymip::lod::{
    LodWord, cone_lod, cone_lod_batch, table_lod, table_lod_batch, table_lod_norm_batch,
};
use raymip::log2::fast::NormPl;
use raymip::texture::storage::mip::Texel;
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip::units::{Accurate, Delta, Depth, Fast, Lod, Log2Pb, PathLength, Width};
use raymip_demo_firmware::inputs::{self, Draws, N};
use raymip_demo_firmware::probe;
use raymip_demo_firmware::probes::{
    self, Images, Meter, SampleIn, Subjects, Tex, TexFast, rm_batch_bilinear, rm_batch_trilinear,
    rm_bench_bilinear, rm_bench_trilinear, rm_bench_trilinear_fast,
};
use raymip_demo_firmware::stack;
use semihosting::{println, process};

/// Stack bytes painted per measurement.
const PAINT: usize = 2048;

type LodIn = (PathLength, Log2Pb);
type LodNormIn = (NormPl, Log2Pb);
type ConeIn = (Width, Delta, Option<U1F31>);
type Instances = [(u32, Depth)];

probe! {
    /// One table LOD.
    fn rm_bench_lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
        table_lod::<Accurate>(pl, pb)
    }
}

probe! {
    /// One ray-cone LOD with the normal term.
    fn rm_bench_cone_lod(w: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
        cone_lod::<Accurate>(w, delta, n_dot_d)
    }
}

probe! {
    /// One FAST table LOD (1024-entry log2 table, no interpolation).
    fn rm_bench_lod_fast(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
        table_lod::<Fast>(pl, pb)
    }
}

probe! {
    /// One FAST ray-cone LOD with the normal term.
    fn rm_bench_cone_lod_fast(w: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
        cone_lod::<Fast>(w, delta, n_dot_d)
    }
}

probe! {
    /// One table LOD in f32.
    fn rm_bench_f32_lod(pl: f32, log2_pb: f32) -> f32 {
        table_lod_f32(pl, log2_pb)
    }
}

probe! {
    /// One ray-cone LOD with the normal term in f32.
    fn rm_bench_f32_cone_lod(w: f32, delta: f32, n_dot_d: Option<f32>) -> f32 {
        cone_lod_f32(w, delta, n_dot_d)
    }
}

probe! {
    /// One bilinear sample at the nearest level in f32.
    fn rm_bench_f32_bilinear(s: &SamplerF32<'_>, u: f32, v: f32, lod: f32) -> Texel {
        s.sample(u, v, lod, Mode::BilinearNearestLevel)
    }
}

probe! {
    /// One trilinear sample in f32.
    fn rm_bench_f32_trilinear(s: &SamplerF32<'_>, u: f32, v: f32, lod: f32) -> Texel {
        s.sample(u, v, lod, Mode::Trilinear)
    }
}

probe! {
    /// A batch of table LODs.
    fn rm_batch_lod(hits: &[LodIn], out: &mut [Option<Lod>]) -> usize {
        table_lod_batch::<Accurate>(hits, out)
    }
}

probe! {
    /// A batch of ray-cone LODs.
    fn rm_batch_cone_lod(hits: &[ConeIn], out: &mut [Lod]) -> usize {
        cone_lod_batch::<Accurate>(hits, out)
    }
}

probe! {
    /// A batch of FAST table LODs (one `LodWord` per hit).
    fn rm_batch_lod_fast(hits: &[LodNormIn], out: &mut [LodWord]) -> usize {
        table_lod_norm_batch(hits, out)
    }
}

probe! {
    /// A batch of FAST ray-cone LODs.
    fn rm_batch_cone_lod_fast(hits: &[ConeIn], out: &mut [Lod]) -> usize {
        cone_lod_batch::<Fast>(hits, out)
    }
}

probe! {
    /// The instance records of one instance: called 64 times with the
    /// discrete selector, then 64 times with the stochastic one.
    fn rm_bench_geomlod(sel: &Selector, inst: (u32, Depth), out: &mut [InstanceLod]) -> Result<usize, RecordsFull> {
        sel.fill(core::iter::once(inst), out)
    }
}

probe! {
    /// The instance records of a slice of instances: called with 32 and 64
    /// instances, discrete then stochastic.
    fn rm_batch_geomlod(sel: &Selector, inst: &Instances, out: &mut [InstanceLod]) -> Result<usize, RecordsFull> {
        sel.fill(inst.iter().copied(), out)
    }
}

probe! {
    /// An empty call (baseline of the `minstret` call-inclusive counts).
    fn rm_bench_empty(x: u32) -> u32 {
        x
    }
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

/// The budgets' [`Meter`]: each row's calls through [`measure`] (the QEMU
/// trace counts them by wrapper symbol; the `minstret` statistics of these
/// rows are not printed), in the order of [`probes::sampler_rows`].
struct Traced;

impl Meter for Traced {
    #[inline(always)]
    fn row<I: Copy>(&mut self, _key: &str, xs: &[I; N], call: impl FnMut(I) -> u32) {
        measure(xs, call);
    }

    #[inline(always)]
    fn pairs<S, I: Copy>(
        &mut self,
        _keys: [&str; 2],
        s: &mut S,
        xs: &[I; N],
        mut prepare: impl FnMut(&mut S),
        mut call: impl FnMut(&mut S, I) -> u32,
    ) {
        measure(xs, |x| {
            prepare(s);
            let a = call(s, x);
            a ^ call(s, x)
        });
    }

    #[inline(always)]
    fn batch(&mut self, _key: &str, mut call: impl FnMut(usize) -> usize) {
        for n in [N / 2, N] {
            bb(call(n));
        }
    }
}

/// Environment map (feature `envmap`): the cone lod without and with
/// the pole term, the ray-differential lod (with `raydiff`) and the
/// direction → `(u, v)` mapping, each its own wrapper.
#[cfg(feature = "envmap")]
mod env {
    use raymip::lod::envmap::{EnvMap, direction_uv};
    use raymip::units::{Lod, Spread, TexCoord, UnitVec};
    use raymip_demo_firmware::probe;

    probe! {
        /// Cone lod, equator texel (no direction).
        fn rm_bench_env_cone(m: &EnvMap, g: Spread) -> Lod {
            m.cone_lod(g, None)
        }
    }

    probe! {
        /// Cone lod with the pole term of the direction.
        fn rm_bench_env_cone_lat(m: &EnvMap, g: Spread, d: UnitVec) -> Lod {
            m.cone_lod(g, Some(d))
        }
    }

    #[cfg(feature = "raydiff")]
    probe! {
        /// Ray-differential lod with the pole term.
        fn rm_bench_env_raydiff(m: &EnvMap, dx: raymip::path::raydiff::DirDiff, dy: raymip::path::raydiff::DirDiff, d: UnitVec) -> Lod {
            m.raydiff_lod(dx, dy, Some(d))
        }
    }

    probe! {
        /// The lat-long `(u, v)` of a direction.
        fn rm_bench_env_uv(d: UnitVec) -> (TexCoord, TexCoord) {
            direction_uv(d)
        }
    }
}

/// The environment-map rows (own generator): 64 calls of each
/// `rm_bench_env_*` wrapper on a 2048 × 1024 map.
#[cfg(feature = "envmap")]
#[inline(always)]
fn envmap_rows() {
    let mut rng = inputs::XorShift32(inputs::SEED ^ 0xE0E0);
    let env_in = inputs::draw(&mut rng, inputs::envmap);
    let Ok(map) = raymip::lod::envmap::EnvMap::new(2048, 1024) else {
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
    {
        use raymip::path::raydiff::DirDiff;
        let rd_in =
            env_in.map(|(_, d, dx, dy)| (d, DirDiff::from_i2f30(dx), DirDiff::from_i2f30(dy)));
        measure(&rd_in, |(d, dx, dy)| {
            env::rm_bench_env_raydiff(&map, dx, dy, d).to_bits() as u32
        });
    }
    measure(&env_in, |(_, d, ..)| {
        let (u, v) = env::rm_bench_env_uv(d);
        (u.to_bits() ^ v.to_bits()) as u32
    });
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
    par: &mut Subjects<'_>,
    geomlod: &[(&str, Selector); 2],
) {
    let Draws {
        empty: empty_in,
        lod: lod_in,
        cone: cone_in,
        bilinear: bil_in,
        trilinear: tri_in,
        aniso: aniso_in,
        mut rng,
    } = Draws::new();

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
        rm_bench_f32_cone_lod(w.to_num(), d.to_num(), c.map(|c| c.to_num())).to_bits()
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
    let mut lod_words = [LodWord::UNTEXTURED; N];
    let mut cone_out = [Lod::ZERO; N];
    let mut tex_out = [0; N];
    // The FAST batch reads the normalised Pl a ray-stack entry keeps
    // (`PathState::pl_norm`, made by `advance`): converted here.
    let lod_norm_in = lod_in.map(|(pl, pb)| (NormPl::new(pl), pb));
    for n in [N / 2, N] {
        bb(rm_batch_lod(bb(&lod_in[..n]), &mut lod_out));
        bb(rm_batch_cone_lod(bb(&cone_in[..n]), &mut cone_out));
        bb(rm_batch_lod_fast(bb(&lod_norm_in[..n]), &mut lod_words));
        bb(rm_batch_cone_lod_fast(bb(&cone_in[..n]), &mut cone_out));
        bb(rm_batch_bilinear(tex, bb(&bil_in[..n]), &mut tex_out));
        bb(rm_batch_trilinear(tex, bb(&tri_in[..n]), &mut tex_out));
    }
    bb((&lod_out, &lod_words, &cone_out, &tex_out));

    // The sampler-state (`ts_*`) rows and the rest of the sampler matrix
    // (`probes::sampler_rows`): the bilinear/trilinear inputs above, BC1 in
    // pairs (cache emptied outside the counted call; then the same sample).
    probes::sampler_rows(&mut Traced, par, &bil_in, &tri_in, &aniso_in);

    // Geometric LOD: one instance per call, then 32 and 64 per call.
    let inst: [(u32, Depth); N] = inputs::instances(&mut rng, 0);
    let mut rec = [InstanceLod::default(); 2 * N];
    for (_, sel) in geomlod {
        measure(&inst, |x| {
            rm_bench_geomlod(sel, x, &mut rec).unwrap_or(usize::MAX) as u32
        });
    }
    for (name, sel) in geomlod {
        for n in [N / 2, N] {
            let r = rm_batch_geomlod(sel, bb(&inst[..n]), &mut rec);
            if n == N {
                println!("geomlod {name}: {} records", r.unwrap_or(0));
            }
        }
    }
    bb(&rec);

    // The ray-differential rows (`probes::raydiff_rows`, own generator) and
    // the ray-stack entry size with the feature.
    #[cfg(feature = "raydiff")]
    {
        if probes::raydiff_rows(&mut Traced).is_none() {
            process::exit(1)
        }
        println!(
            "path state raydiff: {} bytes",
            core::mem::size_of::<raymip::path::raystack::PathState>()
        );
    }
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

raymip_demo_entry::main! {
    let Some((g, p)) = raymip_demo_scene::tex0_pow2() else {
        process::exit(1)
    };
    let Some(texf) = SamplerF32::new(g, &raymip_demo_scene::TEX0, AddressMode::Wrap) else {
        process::exit(1)
    };
    let mut tex: Tex = Sampler::new(p);
    let images = Images::new();
    let Some(mut par) = Subjects::new(g, p, &images) else {
        process::exit(1)
    };
    let (Some(discrete), Some(stochastic)) = (
        inputs::selector(LodMode::Discrete),
        inputs::selector(LodMode::Stochastic(inputs::TRANSITION)),
    ) else {
        process::exit(1)
    };
    let geomlod = [("discrete", discrete), ("stochastic", stochastic)];
    let mut texfast = Sampler::new(p);
    rm_budget_driver(&mut tex, &mut texfast, &texf, &mut par, &geomlod);
    process::exit(0)
}
