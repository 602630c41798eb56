//! Linker set-up for the demo binaries: the layout is the firmware
//! template's `templates/firmware/memory.x` (one file for both QEMU targets,
//! see its comments), or `demo/softcore/memory.x` with the feature
//! `softcore` (the PicoRV32 SoC), or `demo/softcore/litex/memory.x` with the
//! feature `litex` (the LiteX SoC). The `-T`
//! arguments are given here rather than as `rustflags`, because a
//! `RUSTFLAGS` variable would replace the config's `rustflags`.

use std::env;
use std::path::PathBuf;

fn main() {
    let manifest =
        PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let root = manifest
        .join("../..")
        .canonicalize()
        .expect("repository root exists");
    let dir = if env::var_os("CARGO_FEATURE_SOFTCORE").is_some() {
        root.join("demo/softcore")
    } else if env::var_os("CARGO_FEATURE_LITEX").is_some() {
        root.join("demo/softcore/litex")
    } else {
        root.join("templates/firmware")
    };
    println!("cargo:rustc-link-search={}", dir.display());
    println!("cargo:rerun-if-changed={}", dir.join("memory.x").display());
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    match arch.as_str() {
        // cortex-m-rt's link.x INCLUDEs memory.x.
        "arm" => println!("cargo:rustc-link-arg-bins=-Tlink.x"),
        // riscv-rt wants memory.x first (its link.x does not include it).
        "riscv32" => {
            println!("cargo:rustc-link-arg-bins=-Tmemory.x");
            println!("cargo:rustc-link-arg-bins=-Tlink.x");
        }
        _ => {}
    }
}
