//! Cycles of the sampler-matrix calls on the PicoRV32 soft core
//! (feature `softcore`; `scripts/softcore` runs it on the Verilator model
//! of `demo/softcore/soc.v` beside `cycles` and writes the matrix table of
//! BUDGETS.md's soft-core block). The ray differentials are a second
//! binary, `cycles-raydiff` (both together do not fit the SoC's 128 KiB).
//!
//! The wrappers, their subjects and the order of the calls are the QEMU
//! budgets' ([`probes::sampler_rows`], also driven by `src/bin/budget.rs`),
//! on the same inputs ([`Draws`]: the same seed, the budgets' order). The
//! counts are [`CycleMeter`]'s: the core's `cycle` and `instret` counters
//! read around every call, call-inclusive (argument moves, the call, the
//! return) minus the counter reads themselves; a BC1 pair is
//! counted per call, the fill (cache emptied outside the count) then the
//! hit. PicoRV32 is deterministic: a second run prints the same numbers.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use raymip_demo_firmware::counters::CycleMeter;
use raymip_demo_firmware::exit;
use raymip_demo_firmware::inputs::Draws;
use raymip_demo_firmware::probes::{self, Images, Subjects};

raymip_demo_entry::main! {
    let Some((g, p)) = raymip_demo_scene::tex0_pow2() else {
        exit(1)
    };
    let images = Images::new();
    let Some(mut subjects) = Subjects::new(g, p, &images) else {
        exit(1)
    };
    let d = Draws::new();
    let mut m = CycleMeter::new();
    probes::sampler_rows(&mut m, &mut subjects, &d.bilinear, &d.trilinear, &d.aniso);
    exit(0)
}
