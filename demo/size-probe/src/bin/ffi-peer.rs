//! Code-size probe: in Rust, the calls of the C ABI's size probe 2
//! (`tests/c/size_probe.c`: path state, ray stack, table lod and clamp,
//! one RGBA8 wrap sampler and a sample with a run-time mode), built with
//! the C ABI's feature set (the four defaults). `scripts/c-abi` subtracts
//! `features-base` and compares the C image's raymip code with this.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
// The shared panic handler.
use raymip_size_probe as _;

use raymip::lod::{clamp_lod, table_lod};
use raymip::path::raystack::{PathState, RayStack};
use raymip::setup::camera::PixelSpread;
use raymip::texture::storage::mip::{Geometry, Pyramid};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Lod, Log2Pb, PathLength, Spread, TexCoord};

static TEXELS: [u32; 85] = [0; 85];

raymip_demo_entry::main! {
    let mut acc = 0u32;
    if let Ok(spread) = PixelSpread::from_angle(bb(Spread::from_bits(1 << 20))) {
        let mut stack: RayStack = RayStack::new();
        let s = PathState::primary(&spread, 0xFF)
            .advance(bb(PathLength::from_bits(1 << 33)))
            .bounce(bb(Spread::ZERO));
        let _ = bb(stack.push(s));
        let s = stack.pop().unwrap_or(s);
        let levels = bb(4u8);
        let lod = clamp_lod(
            table_lod::<Accurate>(s.pl, bb(Log2Pb::from_bits(0))).unwrap_or(Lod::ZERO),
            levels,
        );
        if let Ok(g) = Geometry::new(8, 8, levels)
            && let Ok(p) = Pyramid::new(g, bb(&TEXELS[..]))
        {
            let mut sampler = Sampler::wrap(p);
            let mode = Mode::from_index(bb(0)).unwrap_or(Mode::Trilinear);
            acc = sampler.sample(bb(TexCoord::ZERO), bb(TexCoord::ZERO), lod, mode);
        }
    }
    bb(acc);
    semihosting::process::exit(0)
}
