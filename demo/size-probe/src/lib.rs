//! Shared part of the code-size probes: a panic handler that exits with
//! code 101 without formatting anything, so a probe's size is the library
//! code it calls plus only the panic call sites that survive.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

/// Side of the feature-set probes' texture (scripts/features).
pub const TEX_SIZE: u32 = 32;
/// Stored levels of that texture (32×32 down to 1×1).
pub const TEX_LEVELS: u8 = 6;
/// Texels of that pyramid.
pub const TEX_LEN: usize =
    raymip::texture::storage::mip::pyramid_len(TEX_SIZE, TEX_SIZE, TEX_LEVELS);

/// The feature-set probes' pyramid: a fixed pseudo-random pattern (the
/// size of the code that reads it does not depend on its values).
pub static TEX: [u32; TEX_LEN] = {
    let mut t = [0u32; TEX_LEN];
    let mut x = 0x9E37_79B9u32;
    let mut i = 0;
    while i < TEX_LEN {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        t[i] = x;
        i += 1;
    }
    t
};

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    semihosting::process::exit(101)
}
