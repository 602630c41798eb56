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

/// The path part both full probes measure: a primary path of `$spread`
/// advanced one segment and bounced, pushed on a ray stack and popped off
/// it, and the clamped table lod of entry 0 of the `PbTable` `$table` for
/// `$levels` levels. Evaluates to `(popped state, that entry's log2 Pb,
/// lod)`. A macro, expanded in each probe's `main`, so that the probe's
/// code is the calls themselves (a function, even always inlined, is
/// compiled differently by a few bytes).
#[macro_export]
macro_rules! one_bounce {
    ($spread:expr, $table:expr, $levels:expr) => {{
        use core::hint::black_box as bb;
        use raymip::path::raystack::{PathState, RayStack};
        use raymip::units::{Accurate, Lod, Log2Pb, PathLength, Spread};
        let mut stack: RayStack = RayStack::new();
        let st = PathState::primary($spread, bb(0xFF))
            .advance(bb(PathLength::from_bits(1 << 33)))
            .bounce(bb(Spread::ZERO));
        let _ = bb(stack.push(st));
        let st = stack.pop().unwrap_or(st);
        let pb = $table.get(bb(0)).unwrap_or(Log2Pb::UNTEXTURED);
        let lod =
            raymip::lod::table_lod_clamped::<Accurate>(st.pl, pb, $levels).unwrap_or(Lod::ZERO);
        (st, pb, lod)
    }};
}

/// Sizes on this target of the types a firmware keeps per path and per
/// texture, as the sizes of symbols: `scripts/features` reads them with
/// `nm -S` for each feature set (`raymip-host memory` uses them). Zeroed
/// (`.bss`), and kept in both feature-set probes by [`keep_type_sizes`]:
/// their `.text`/`.rodata` difference is unchanged.
pub mod type_sizes {
    use core::mem::size_of;
    use raymip::path::raystack::PathState;
    use raymip::texture::address::Wrap;
    use raymip::texture::storage::mip::Pyramid;
    use raymip::texture::{Cfg, Sampler};

    /// One ray-stack entry.
    pub static RAYMIP_SIZE_PATH_STATE: [u8; size_of::<PathState>()] = [0; size_of::<PathState>()];
    /// A wrapping ACCURATE sampler of a pyramid in memory.
    pub static RAYMIP_SIZE_SAMPLER: [u8; size_of::<Sampler<Pyramid<'static>, Cfg<Wrap>>>()] =
        [0; size_of::<Sampler<Pyramid<'static>, Cfg<Wrap>>>()];
    /// A texel cache of 8 sets × 2 ways in front of a pyramid.
    #[cfg(feature = "cache")]
    pub static RAYMIP_SIZE_CACHE_8X2: [u8; size_of::<
        raymip::texture::storage::cache::TexelCache<Pyramid<'static>, 8, 2>,
    >()] = [0; size_of::<raymip::texture::storage::cache::TexelCache<Pyramid<'static>, 8, 2>>()];
}

/// Keeps the [`type_sizes`] symbols in the image (one out-of-line call in
/// each probe).
#[inline(never)]
pub fn keep_type_sizes() {
    core::hint::black_box(&type_sizes::RAYMIP_SIZE_PATH_STATE);
    core::hint::black_box(&type_sizes::RAYMIP_SIZE_SAMPLER);
    #[cfg(feature = "cache")]
    core::hint::black_box(&type_sizes::RAYMIP_SIZE_CACHE_8X2);
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    semihosting::process::exit(101)
}
