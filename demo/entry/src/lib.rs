//! The reset entry point of the bare-metal binaries (demo, budget, parity,
//! cycles, the size probes): [`main!`] picks the runtime's `entry` attribute
//! for the target, so no binary repeats the per-target `use` lines.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

/// `raymip_demo_entry::main! { body }` defines `fn main() -> !` with `body`
/// as the program's entry: `cortex_m_rt::entry` on Arm, `riscv_rt::entry`
/// on RISC-V (the calling crate depends on the runtime of its target).
#[macro_export]
macro_rules! main {
    ($($body:tt)*) => {
        #[cfg_attr(target_arch = "arm", cortex_m_rt::entry)]
        #[cfg_attr(target_arch = "riscv32", riscv_rt::entry)]
        fn main() -> ! {
            $($body)*
        }
    };
}
