//! A bare-metal firmware skeleton around raymip: the runtime's entry point,
//! a panic handler, the per-hit flow of `flow.rs`, and its report on the
//! semihosting console. Exits with code 0, or 1 when the set-up failed or
//! the ray stack dropped a continuation.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

mod flow;

use core::fmt;

use semihosting::println;

#[cfg_attr(target_arch = "arm", cortex_m_rt::entry)]
#[cfg_attr(target_arch = "riscv32", riscv_rt::entry)]
fn main() -> ! {
    let target = if cfg!(target_arch = "arm") {
        "Cortex-M4F"
    } else {
        "RV32IMAC"
    };
    println!(
        "my-firmware on {target}: {} bounces, two continuations per hit",
        flow::BOUNCES
    );
    let report = match flow::run() {
        Ok(report) => report,
        Err(what) => {
            println!("set-up failed: {what}");
            exit(1)
        }
    };
    let mut hits = 0;
    for (depth, at) in report.depths.iter().enumerate() {
        println!(
            "depth {depth:2}: {:4} hits, lod {} (bits {}), rgba {:#010x}",
            at.hits,
            Levels(at.lod),
            at.lod,
            at.rgba
        );
        hits += at.hits;
    }
    println!(
        "ray stack: at most {} of {} entries, {} continuations dropped; {hits} hits",
        report.stack_max,
        flow::STACK,
        report.dropped
    );
    exit(if report.dropped == 0 { 0 } else { 1 })
}

/// An I8F8 lod printed in levels with two decimals, by integer arithmetic
/// (formatting a float would link tens of kilobytes).
struct Levels(i16);

impl fmt::Display for Levels {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let bits = i32::from(self.0);
        let hundredths = (bits.abs() * 100 + 128) / 256;
        let sign = if bits < 0 { "-" } else { "" };
        write!(f, "{sign}{}.{:02}", hundredths / 100, hundredths % 100)
    }
}

/// Ends the program with exit code `code` (semihosting: QEMU's exit status).
fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}

/// A panic (none is reachable from the flow) exits with code 101 without
/// formatting its message (which would link the panic-message machinery).
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    exit(101)
}
