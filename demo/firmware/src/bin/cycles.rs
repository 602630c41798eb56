//! Cycles of single per-hit calls on the PicoRV32 soft core (feature
//! `softcore`; `scripts/softcore` runs it on the Verilator model of
//! `demo/softcore/soc.v` and writes BUDGETS.md's soft-core block).
//!
//! The calls and their inputs are those of the QEMU budgets
//! (`src/bin/budget.rs`): the same [`inputs`] draws, from the same seed, in
//! the same order (empty call, table lod, cone lod, bilinear, trilinear), so
//! each kind sees the same 64 inputs (the FAST lod paths reuse the table and
//! cone lod inputs). Around every call the core's `cycle`
//! and `instret` counters are read (`rdcycle`/`rdinstret`); each count is
//! call-inclusive (argument moves, the call, the return) minus the same
//! count around an empty call (the counter reads themselves). PicoRV32 is
//! deterministic: a second run prints the same numbers.
//!
//! Output, one line per call kind:
//! `call NAME: n 64 cycles min A sum B max C instret min D sum E max F`.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;

use fixed::types::{I16F16, U1F31};
use raymip::filter::{Address, Mode, Sampler, TexCoord};
use raymip::lod::{Lod, cone_lod, cone_lod_fast, table_lod, table_lod_fast};
use raymip::mip::{Pyramid, Texel};
use raymip::raystack::{PathLength, Width};
use raymip::table::Log2Pb;
use raymip_demo_firmware::counters::{Stat, cycles32, instret32};
use raymip_demo_firmware::inputs::{self, N, Rng};
use raymip_demo_firmware::{exit, println};

type Tex = Sampler<Pyramid<'static>>;

#[inline(never)]
fn empty(x: u32) -> u32 {
    x
}

#[inline(never)]
fn lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    table_lod(pl, pb)
}

#[inline(never)]
fn cone(w: Width, delta: I16F16, n_dot_d: Option<U1F31>) -> Lod {
    cone_lod(w, delta, n_dot_d)
}

#[inline(never)]
fn lod_fast(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    table_lod_fast(pl, pb)
}

#[inline(never)]
fn cone_fast(w: Width, delta: I16F16, n_dot_d: Option<U1F31>) -> Lod {
    cone_lod_fast(w, delta, n_dot_d)
}

#[inline(never)]
fn bilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

#[inline(never)]
fn trilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// Draws the [`N`] inputs of one kind.
fn draw<T>(rng: &mut Rng, mut f: impl FnMut(&mut Rng) -> T) -> [T; N] {
    core::array::from_fn(|_| f(rng))
}

/// Counts cycles and instructions around each call of `call` on `xs`.
#[inline(always)]
fn measure<I: Copy, O>(xs: &[I; N], mut call: impl FnMut(I) -> O) -> (Stat, Stat) {
    let (mut cy, mut ir) = (Stat::EMPTY, Stat::EMPTY);
    for &x in xs {
        let x = bb(x);
        let c0 = cycles32();
        let i0 = instret32();
        let y = call(x);
        let i1 = instret32();
        let c1 = cycles32();
        bb(y);
        cy.add(c1.wrapping_sub(c0));
        ir.add(i1.wrapping_sub(i0));
    }
    (cy, ir)
}

raymip_demo_entry::main! {
    let Some(g) = raymip_demo_scene::tex_geometry() else {
        exit(1)
    };
    let Ok(p) = Pyramid::new(g, &raymip_demo_scene::TEX0) else {
        exit(1)
    };
    let mut tex = Sampler::new(p, Address::Wrap);

    let mut rng = Rng(inputs::SEED);
    let empty_in = draw(&mut rng, Rng::next);
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
    exit(0)
}
