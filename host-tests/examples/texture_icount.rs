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

use raymip::baseline_f32::SamplerF32;
use raymip::texture::storage::mip::Pyramid;
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip_host::workload::{random_inputs, random_pyramid, to_fixed};

/// Samples per run.
const N: usize = 100_000;

fn main() -> ExitCode {
    let variant = std::env::args().nth(1).unwrap_or_default();
    let Ok((g, buf)) = random_pyramid(256) else {
        return ExitCode::FAILURE;
    };
    let inp = random_inputs(N);
    let fin = to_fixed(&inp);
    let Ok(p) = Pyramid::new(g, &buf) else {
        return ExitCode::FAILURE;
    };
    let mut fixed = Sampler::wrap(p);
    let Some(float) = SamplerF32::new(g, &buf, AddressMode::Wrap) else {
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
