//! Cycles of the ray-differential calls on the PicoRV32 soft
//! core (features `softcore` and `raydiff`; `scripts/softcore` runs it on
//! the Verilator model of `demo/softcore/soc.v` beside `cycles` and writes
//! the ray-differential table of BUDGETS.md's soft-core block).
//!
//! The wrappers, their inputs and the order of the calls are the QEMU
//! budgets' ([`probes::raydiff_rows`], also driven by `src/bin/budget.rs`
//! built with `raydiff`), counted by [`CycleMeter`] like `cycles-matrix`.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use raymip_demo_firmware::counters::CycleMeter;
use raymip_demo_firmware::exit;
use raymip_demo_firmware::probes;

raymip_demo_entry::main! {
    let mut m = CycleMeter::new();
    if probes::raydiff_rows(&mut m).is_none() {
        exit(1)
    }
    exit(0)
}
