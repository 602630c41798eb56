//! `libraymip_ffi.a`: the raymip C ABI (`raymip::ffi`, header
//! `include/raymip.h`) as a static library for the host (`cargo build -p
//! raymip-ffi --release`) or a bare-metal target (`--target
//! thumbv7em-none-eabihf`; the library then brings a panic handler that
//! parks the core: no path behind the ABI panics, see
//! `scripts/link-checks`).
#![cfg_attr(target_os = "none", no_std)]
#![forbid(unsafe_code)]

pub use raymip::ffi::*;

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {
        core::hint::spin_loop();
    }
}
