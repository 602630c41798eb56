//! Load-independent cost per sample for the fixed-vs-f32 comparison:
//! run under `valgrind --tool=callgrind` once per variant and subtract the
//! `none` variant (set-up only). Variants: none, bilinear-fixed,
//! bilinear-f32, trilinear-fixed, trilinear-f32.
//!
//! ```text
//! cargo build --release -p raymip-host --example texture_icount
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/examples/texture_icount trilinear-fixed
//! ```

use std::hint::black_box;
use std::process::ExitCode;

use raymip::filter::{Address, Mode, Sampler, TexCoord};
use raymip::lod::Lod;
use raymip::mip::{Geometry, Pyramid, full_levels, generate};
use raymip_host::texf32::SamplerF32;

/// Samples per run.
const N: usize = 100_000;

fn main() -> ExitCode {
    let variant = std::env::args().nth(1).unwrap_or_default();
    let size = 256;
    let Ok(g) = Geometry::new(size, size, full_levels(size, size)) else {
        return ExitCode::FAILURE;
    };
    let mut buf = vec![0u32; g.len()];
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for t in &mut buf[..(size * size) as usize] {
        *t = next() as u32;
    }
    if generate(&g, &mut buf).is_err() {
        return ExitCode::FAILURE;
    }
    let mut unit = move || (next() >> 40) as f32 / (1u64 << 24) as f32;
    let inp: Vec<(f32, f32, f32)> = (0..N)
        .map(|_| {
            let lod = (unit() * 6.0).floor() + 0.125 + 0.75 * unit();
            (unit() * 4.0 - 2.0, unit() * 4.0 - 2.0, lod)
        })
        .collect();
    let fin: Vec<(TexCoord, TexCoord, Lod)> = inp
        .iter()
        .map(|&(u, v, l)| {
            (
                TexCoord::from_num(u),
                TexCoord::from_num(v),
                Lod::from_num(l),
            )
        })
        .collect();
    let Ok(p) = Pyramid::new(g, &buf) else {
        return ExitCode::FAILURE;
    };
    let mut fixed = Sampler::new(p, Address::Wrap);
    let Some(float) = SamplerF32::new(g, &buf, Address::Wrap) else {
        return ExitCode::FAILURE;
    };
    black_box((&fin, &inp));
    let (mode, use_fixed) = match variant.as_str() {
        "none" => return ExitCode::SUCCESS,
        "bilinear-fixed" => (Mode::BilinearNearestLevel, true),
        "bilinear-f32" => (Mode::BilinearNearestLevel, false),
        "trilinear-fixed" => (Mode::Trilinear, true),
        "trilinear-f32" => (Mode::Trilinear, false),
        other => {
            eprintln!("unknown variant {other:?}");
            return ExitCode::FAILURE;
        }
    };
    let mut acc = 0u32;
    if use_fixed {
        for &(u, v, l) in black_box(&fin) {
            acc ^= fixed.sample(u, v, l, mode);
        }
    } else {
        for &(u, v, l) in black_box(&inp) {
            acc ^= float.sample(u, v, l, mode);
        }
    }
    println!("{variant}: {N} samples, xor {acc:08x}");
    ExitCode::SUCCESS
}
