//! Cross-target check of the GPU-style sampler: prints the parity line of
//! `raymip_demo_scene::parity` (every texel format, colour space, address
//! mode and filter, hashed) over semihosting; `scripts/demos` compares it
//! with the host's `raymip-demo parity`.
//!
//! Run from `demo/`: `cargo run --release --target thumbv7em-none-eabihf
//! --bin parity` (or `--target riscv32imac-unknown-none-elf`).
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use semihosting::{println, process};

raymip_demo_entry::main! {
    match raymip_demo_scene::parity::checksum() {
        Some(line) => {
            println!("{line}");
            process::exit(0)
        }
        None => {
            println!("error: parity set-up failed");
            process::exit(1)
        }
    }
}
