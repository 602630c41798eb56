//! The raymip bare-metal demo: renders the built-in scene tile through the
//! firmware path, prints the pixel checksum and the per-stage counters over
//! semihosting and exits with code 0 (1 if the generated data is invalid or
//! the Pb table or a MIP pyramid rebuilt at start-up differs from the
//! static data).
//!
//! Run from `demo/`: `cargo run --release --target thumbv7em-none-eabihf`
//! (QEMU mps2-an386, Cortex-M4) or `--target riscv32imac-unknown-none-elf`
//! (QEMU virt); `scripts/softcore` runs it on the PicoRV32 soft core
//! (feature `softcore`, `riscv32imc-unknown-none-elf`) and on VexRiscv in a
//! LiteX SoC (feature `litex`, `riscv32im-unknown-none-elf`), where it also
//! prints the render's cycles and instructions.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use raymip_demo_firmware::{counters, exit, println, stack};
use raymip_demo_scene::{Fnv1a, HEIGHT, Renderer, WIDTH};

/// Stack bytes painted below the render's caller.
const PAINT_BYTES: usize = 16 * 1024;

raymip_demo_entry::main! {
    let code = run();
    exit(code)
}

/// The render behind a call boundary, so that its whole frame lies in the
/// painted stack (an inlined callee's locals would sit in the caller's frame).
#[inline(never)]
fn render(r: &mut Renderer, h: &mut Fnv1a) {
    r.render(|_, _, rgb| h.write(&rgb));
}

fn run() -> i32 {
    let target = if cfg!(target_arch = "arm") {
        "thumbv7em-none-eabihf (Cortex-M4)"
    } else if cfg!(feature = "softcore") {
        "riscv32imc-unknown-none-elf (PicoRV32 soft core)"
    } else if cfg!(feature = "litex") {
        "riscv32im-unknown-none-elf (VexRiscv in a LiteX SoC)"
    } else {
        "riscv32imac-unknown-none-elf"
    };
    println!("raymip demo on {target}");
    let Some(mut r) = Renderer::new() else {
        println!("error: demo data invalid");
        return 1;
    };
    let mut h = Fnv1a::default();
    // Worst-case stack of the render (stack painting, see the lib docs).
    let top = stack::sp();
    stack::paint(top, PAINT_BYTES);
    let c0 = counters::read();
    render(&mut r, &mut h);
    let c1 = counters::read();
    let used = stack::used(top, PAINT_BYTES);
    println!(
        "checksum: {:#010x} ({}x{} RGB, FNV-1a)",
        h.finish(),
        WIDTH,
        HEIGHT
    );
    println!("counters: {}", r.counters);
    println!("stack: {used} bytes used by the render (painted {PAINT_BYTES})");
    if cfg!(feature = "counters") {
        let (cycles, instret) = (c1.cycles - c0.cycles, c1.instret - c0.instret);
        println!("render: {cycles} cycles, {instret} instructions (rdcycle/rdinstret)");
    }
    if r.counters.table_mismatches != 0 || r.counters.pyramid_mismatches != 0 {
        return 1;
    }
    0
}
