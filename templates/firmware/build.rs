//! Linker set-up: the runtime's linker script `link.x` with this crate's
//! `memory.x`. Without `-Tlink.x` the linker finds no entry point and no
//! vector table, keeps nothing and writes an empty image without a word of
//! warning; `scripts/templates` in the raymip checkout checks the sections.

use std::env;
use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    println!("cargo:rustc-link-search={}", dir.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    match env::var("CARGO_CFG_TARGET_ARCH").as_deref() {
        // cortex-m-rt's link.x INCLUDEs memory.x.
        Ok("arm") => println!("cargo:rustc-link-arg-bins=-Tlink.x"),
        // riscv-rt wants memory.x first (its link.x does not include it).
        Ok("riscv32") => {
            println!("cargo:rustc-link-arg-bins=-Tmemory.x");
            println!("cargo:rustc-link-arg-bins=-Tlink.x");
        }
        _ => {}
    }
}
