//! Cycles of single per-hit calls on a soft core (feature `softcore`:
//! PicoRV32, or `litex`: VexRiscv; `scripts/softcore` runs it on the
//! Verilator models of `demo/softcore/soc.v` and of the LiteX SoC and
//! writes BUDGETS.md's soft-core block).
//!
//! The calls and their inputs are those of the QEMU budgets
//! (`src/bin/budget.rs`): the same [`inputs`] draws, from the same seed, in
//! the same order (empty call, table lod, cone lod, bilinear, trilinear), so
//! each kind sees the same 64 inputs (the FAST lod paths reuse the table and
//! cone lod inputs). Around every call the core's `cycle`
//! and `instret` counters are read (`rdcycle`/`rdinstret`); each count is
//! call-inclusive (argument moves, the call, the return) minus the same
//! count around an empty call (the counter reads themselves). On a cached
//! core every series first runs once untimed ([`WARM_UP`]). The
//! simulated cores are deterministic: a second run prints the same numbers.
//!
//! Then the batch entry points (`table_lod_batch`, `cone_lod_batch`, their
//! FAST twins, `Sampler::sample_batch` bilinear and trilinear), each called once on the
//! first 32 and once on all 64 inputs of its kind, as the QEMU budgets do:
//! the steady cost per hit is the difference over 32.
//!
//! Output, one line per call kind:
//! `call NAME: n 64 cycles min A sum B max C instret min D sum E max F`,
//! and one per batch kind:
//! `batch NAME: n32 cycles A instret B n64 cycles C instret D` (minus the
//! empty measurement).
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;

use fixed::types::U1F31;
use raymip::lod::{
    LodWord, cone_lod, cone_lod_batch, table_lod, table_lod_batch, table_lod_norm_batch,
};
use raymip::log2::fast::NormPl;
use raymip::texture::storage::mip::Texel;
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Delta, Fast, Lod, Log2Pb, PathLength, TexCoord, Width};
use raymip_demo_firmware::counters::{WARM_UP, measure, once};
use raymip_demo_firmware::inputs::{self, N, XorShift32};
use raymip_demo_firmware::{exit, measured_calls, println};

use raymip_demo_firmware::probes::Tex;

#[inline(never)]
fn empty(x: u32) -> u32 {
    x
}

measured_calls! {
    fn lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> = table_lod::<Accurate>;
    fn cone(w: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod = cone_lod::<Accurate>;
    fn lod_fast(pl: PathLength, pb: Log2Pb) -> Option<Lod> = table_lod::<Fast>;
    fn cone_fast(w: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod = cone_lod::<Fast>;
    fn lod_batch(hits: &[(PathLength, Log2Pb)], out: &mut [Option<Lod>]) -> usize = table_lod_batch::<Accurate>;
    fn cone_batch(hits: &[(Width, Delta, Option<U1F31>)], out: &mut [Lod]) -> usize = cone_lod_batch::<Accurate>;
    fn lod_fast_batch(hits: &[(NormPl, Log2Pb)], out: &mut [LodWord]) -> usize =
        table_lod_norm_batch;
    fn cone_fast_batch(hits: &[(Width, Delta, Option<U1F31>)], out: &mut [Lod]) -> usize =
        cone_lod_batch::<Fast>;
}

#[inline(never)]
fn bilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

#[inline(never)]
fn trilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

#[inline(never)]
fn sample_batch(
    s: &mut Tex,
    hits: &[(TexCoord, TexCoord, Lod)],
    mode: Mode,
    out: &mut [Texel],
) -> usize {
    s.sample_batch(hits, mode, out)
}

/// Draws the [`N`] inputs of one kind.
fn draw<T>(rng: &mut XorShift32, mut f: impl FnMut(&mut XorShift32) -> T) -> [T; N] {
    core::array::from_fn(|_| f(rng))
}

raymip_demo_entry::main! {
    let Some((_, p)) = raymip_demo_scene::tex0_pow2() else {
        exit(1)
    };
    let mut tex: Tex = Sampler::new(p);

    let mut rng = XorShift32(inputs::SEED);
    let empty_in = draw(&mut rng, XorShift32::next_u32);
    let lod_in = draw(&mut rng, inputs::table_lod);
    let cone_in = draw(&mut rng, inputs::cone_lod);
    let bil_in = draw(&mut rng, inputs::bilinear);
    let tri_in = draw(&mut rng, inputs::trilinear);

    let (base_cy, base_ir) = measure(&empty_in, empty);
    let results = [
        ("lod", measure(&lod_in, |(pl, pb)| lod(pl, pb))),
        ("cone_lod", measure(&cone_in, |(w, d, c)| cone(w, d, c))),
        ("lod_fast", measure(&lod_in, |(pl, pb)| lod_fast(pl, pb))),
        (
            "cone_lod_fast",
            measure(&cone_in, |(w, d, c)| cone_fast(w, d, c)),
        ),
        (
            "bilinear",
            measure(&bil_in, |(u, v, l)| bilinear(&mut tex, u, v, l)),
        ),
        (
            "trilinear",
            measure(&tri_in, |(u, v, l)| trilinear(&mut tex, u, v, l)),
        ),
    ];
    // The empty call is the baseline: constant on an in-order core without
    // caches (min = max); its minimum is subtracted.
    println!(
        "baseline: cycles min {} max {} instret min {} max {}",
        base_cy.min, base_cy.max, base_ir.min, base_ir.max
    );
    for (name, (cy, ir)) in results {
        let (cy, ir) = (cy.minus(base_cy.min, N), ir.minus(base_ir.min, N));
        println!(
            "call {name}: n {N} cycles min {} sum {} max {} instret min {} sum {} max {}",
            cy.min, cy.sum, cy.max, ir.min, ir.sum, ir.max
        );
    }
    // Batches: 32 then 64 hits of each kind, one call each.
    let mut lod_out = [None; N];
    // The FAST batch reads the ray stack's normalised Pl (made outside the
    // count) and writes one word per hit.
    let lod_norm_in = lod_in.map(|(pl, pb)| (NormPl::new(pl), pb));
    let mut lod_words = [LodWord::UNTEXTURED; N];
    let mut cone_out = [Lod::ZERO; N];
    let mut tex_out = [Texel::default(); N];
    let batch = |name: &str, f: &mut dyn FnMut(usize) -> (u32, u32)| {
        if WARM_UP {
            bb(f(N));
        }
        let (c32, i32_) = f(32);
        let (c64, i64_) = f(N);
        let (bc, bi) = (base_cy.min, base_ir.min);
        println!(
            "batch {name}: n32 cycles {} instret {} n64 cycles {} instret {}",
            c32.saturating_sub(bc),
            i32_.saturating_sub(bi),
            c64.saturating_sub(bc),
            i64_.saturating_sub(bi)
        );
    };
    batch("lod", &mut |n| {
        once(|| lod_batch(bb(&lod_in[..n]), &mut lod_out))
    });
    batch("cone_lod", &mut |n| {
        once(|| cone_batch(bb(&cone_in[..n]), &mut cone_out))
    });
    batch("lod_fast", &mut |n| {
        once(|| lod_fast_batch(bb(&lod_norm_in[..n]), &mut lod_words))
    });
    batch("cone_lod_fast", &mut |n| {
        once(|| cone_fast_batch(bb(&cone_in[..n]), &mut cone_out))
    });
    batch("bilinear", &mut |n| {
        once(|| {
            sample_batch(
                &mut tex,
                bb(&bil_in[..n]),
                Mode::BilinearNearestLevel,
                &mut tex_out,
            )
        })
    });
    batch("trilinear", &mut |n| {
        once(|| sample_batch(&mut tex, bb(&tri_in[..n]), Mode::Trilinear, &mut tex_out))
    });

    exit(0)
}
